// capflow/capsule/health: failure detection for a running simulation.
//
// check() after every step looks for
//   * non-finite node positions                                   -> failure "nan"
//   * an element Jacobian changing sign: (t1 x t2) . n_prev <= 0 at a node, n_prev the unit
//     normal at the last good state                                -> failure "jacobian"
//   * runaway node-to-node oscillation: the largest coefficient of the highest Legendre mode
//     P_{NB-1} along any grid line of any element, relative to that element's size, above
//     oscillation_fail (default 2e-2)                             -> failure "oscillation";
//     above oscillation_warn (default 2e-3)                       -> warning (once)
//   * an under-resolved surface: the unit normals at two neighbouring nodes of a grid line
//     differ by more than resolution_warn_angle (default 0.8 rad; geometry::max_normal_turning)
//                                                                  -> warning (once): a tip
//     sharper than NB resolves (raise mesh.nb). Measured at the tips of the validation runs
//     (benchmarks/capsule/volume_flux): 0.50 rad at Skalak Ca=0.45 NE=14 NB=12 (volume leak
//     5e-8 per unit time), 1.0 at fig. 2b NE=6 NB=12 (8e-5), 1.2 at Skalak Ca=1.25 NE=14 NB=10
//     (7e-5), 2.2 at NH Ca=0.4 NE=14 NB=10 (6e-4).
// check_wrinkling() warns (once) when compressive tensions (tension2 < -tol) persist while the
// shape is near steady state (|dD/dt| < rate_tol) - the paper's wrinkling below Ca ~ 0.15.
// Reports name the cause, the simulated time and the location (element, node, position).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "geometry/mesh.h"

namespace capflow::capsule {

enum class HealthLevel { Ok, Warning, Failure };

struct HealthReport {
  HealthLevel level = HealthLevel::Ok;
  std::string cause;    // "nan", "jacobian", "oscillation", "resolution", "wrinkling"
  std::string message;  // plain sentence with time and location
  double indicator = 0; // the oscillation indicator at this check
};

struct HealthOptions {
  double oscillation_warn = 2e-3;
  double oscillation_fail = 2e-2;
  double resolution_warn_angle = 0.8;  // rad between the normals of neighbouring nodes
  double wrinkle_tension = -1e-3;   // tension2 below this is compressive
  double wrinkle_rate = 1e-3;       // |dD/dt| below this counts as near steady
  double wrinkle_duration = 1.0;    // compressive for this long (simulated time) -> warning
};

class HealthMonitor {
 public:
  HealthMonitor(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x0, HealthOptions opt = {});

  // Checks positions x at time t. On Ok/Warning the state becomes the new "last good" state.
  HealthReport check(const Eigen::Matrix3Xd& x, double t);
  // Wrinkling watch: min principal tension (tension2) and where, and |dD/dt| now.
  HealthReport check_wrinkling(double t, double min_tension, const Eigen::Vector3d& where,
                               double d_rate);

  double oscillation_indicator(const Eigen::Matrix3Xd& x) const;

  // State for checkpoints: last good normals (3 x num_local) and the flags.
  const Eigen::Matrix3Xd& normals() const { return normals_; }
  std::vector<double> flags() const {
    return {warned_oscillation_ ? 1.0 : 0.0, warned_wrinkle_ ? 1.0 : 0.0, compressive_since_,
            warned_resolution_ ? 1.0 : 0.0};
  }
  // flags: 4 values as flags() gives, or the first 3 (checkpoints before the resolution check).
  // Throws std::invalid_argument for another count.
  void restore(const Eigen::Matrix3Xd& normals, const std::vector<double>& flags);

 private:
  const geometry::Mesh& mesh_;
  HealthOptions opt_;
  Eigen::MatrixXd modal_last_;  // row vector: nodal values -> coefficient of P_{NB-1}
  Eigen::Matrix3Xd normals_;
  // Positions of the last good state (x0, then every Ok/Warning check): failure messages name
  // a node by where it was, since a failed state's coordinates may be huge or not finite.
  Eigen::Matrix3Xd last_x_;
  bool warned_oscillation_ = false;
  bool warned_wrinkle_ = false;
  bool warned_resolution_ = false;
  double compressive_since_ = -1;
};

}  // namespace capflow::capsule
