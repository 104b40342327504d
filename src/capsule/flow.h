// capflow/capsule/flow: imposed linear flows u_inf(x) = G x (dimensionless, time scale 1/G).
//   planar extension u = (x, -y, 0):  G = diag(1, -1, 0)
//   simple shear     u = (z, 0, 0):   G_xz = 1
//   any constant velocity gradient (traceless for an incompressible flow).
#pragma once

#include <Eigen/Dense>
#include <string>

namespace capflow::capsule {

enum class FlowType { PlanarExtension, SimpleShear, Custom };

struct Flow {
  FlowType type = FlowType::PlanarExtension;
  Eigen::Matrix3d gradient = Eigen::Vector3d(1, -1, 0).asDiagonal();

  static Flow planar_extension();
  static Flow simple_shear();
  // Throws std::invalid_argument unless |trace G| <= 1e-12 (incompressible).
  static Flow custom(const Eigen::Matrix3d& gradient);

  Eigen::Vector3d velocity(const Eigen::Vector3d& x) const { return gradient * x; }
  std::string name() const;
  // The flow in words, read off the gradient (the frames' text block): planar extension "...
  // (stretching along x, compressing along y)", simple shear "... (u = G z along x, vorticity
  // along +y)", otherwise "custom velocity gradient".
  std::string description() const;
};

}  // namespace capflow::capsule
