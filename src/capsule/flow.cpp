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
    case FlowType::PlanarExtension:
      return "planar-extension";
    case FlowType::SimpleShear:
      return "simple-shear";
    case FlowType::Custom:
      return "custom";
  }
  return "custom";
}

namespace {
constexpr const char* kAxis[3] = {"x", "y", "z"};
}  // namespace

std::string Flow::description() const {
  const Eigen::Matrix3d& g = gradient;
  if (type == FlowType::PlanarExtension) {
    int up = 0, down = 0;
    for (int k = 1; k < 3; ++k) {
      if (g(k, k) > g(up, up)) up = k;
      if (g(k, k) < g(down, down)) down = k;
    }
    return std::string("planar extension (stretching along ") + kAxis[up] + ", compressing along " +
           kAxis[down] + ")";
  }
  if (type == FlowType::SimpleShear) {
    int i = 0, j = 1;  // the velocity component i grows along axis j
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (std::abs(g(a, b)) > std::abs(g(i, j))) i = a, j = b;
    const Eigen::Vector3d w(g(2, 1) - g(1, 2), g(0, 2) - g(2, 0), g(1, 0) - g(0, 1));
    int k = 0;
    for (int a = 1; a < 3; ++a)
      if (std::abs(w[a]) > std::abs(w[k])) k = a;
    return std::string("simple shear (u = G ") + kAxis[j] + " along " + kAxis[i] +
           ", vorticity along " + (w[k] > 0 ? "+" : "\u2212") + kAxis[k] + ")";
  }
  return "custom velocity gradient";
}

}  // namespace capflow::capsule
