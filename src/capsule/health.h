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
  std::string cause;    // "nan", "jacobian", "oscillation", "wrinkling"
  std::string message;  // plain sentence with time and location
  double indicator = 0; // the oscillation indicator at this check
};

struct HealthOptions {
  double oscillation_warn = 2e-3;
  double oscillation_fail = 2e-2;
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
    return {warned_oscillation_ ? 1.0 : 0.0, warned_wrinkle_ ? 1.0 : 0.0, compressive_since_};
  }
  void restore(const Eigen::Matrix3Xd& normals, const std::vector<double>& flags) {
    normals_ = normals;
    warned_oscillation_ = flags.at(0) != 0;
    warned_wrinkle_ = flags.at(1) != 0;
    compressive_since_ = flags.at(2);
  }

 private:
  const geometry::Mesh& mesh_;
  HealthOptions opt_;
  Eigen::MatrixXd modal_last_;  // row vector: nodal values -> coefficient of P_{NB-1}
  Eigen::Matrix3Xd normals_;
  bool warned_oscillation_ = false;
  bool warned_wrinkle_ = false;
  double compressive_since_ = -1;
};

}  // namespace capflow::capsule
