#include "capsule/flow.h"

#include <cmath>
#include <stdexcept>

namespace capflow::capsule {

Flow Flow::planar_extension() {
  Flow f;
  f.type = FlowType::PlanarExtension;
  f.gradient = Eigen::Vector3d(1, -1, 0).asDiagonal();
  return f;
}

Flow Flow::simple_shear() {
  Flow f;
  f.type = FlowType::SimpleShear;
  f.gradient.setZero();
  f.gradient(0, 2) = 1.0;
  return f;
}

Flow Flow::custom(const Eigen::Matrix3d& gradient) {
  if (std::abs(gradient.trace()) > 1e-12)
    throw std::invalid_argument("flow gradient must be traceless (incompressible), trace = " +
                                std::to_string(gradient.trace()));
  Flow f;
  f.type = FlowType::Custom;
  f.gradient = gradient;
  return f;
}

std::string Flow::name() const {
  switch (type) {
    case FlowType::PlanarExtension: return "planar-extension";
    case FlowType::SimpleShear: return "simple-shear";
    case FlowType::Custom: return "custom";
  }
  return "custom";
}

}  // namespace capflow::capsule
