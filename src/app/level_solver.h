// capflow/app/level_solver: capflow steady's solver of one level of Ca - it knows nothing of run
// directories, logs or control files: its caller hands it hooks (Hooks) to say what it does,
// to take live edits between time steps and to be stopped.
//
// solve(ca), from the fine grid's state (the previous steady state, rest, or start.from's):
//   1. approach: adaptive time steps (app::TimeStepper on "auto", time.tolerance) until the
//      largest node speed is below kApproachSpeed; the last accepted steps measure the stability
//      limit;
//   2. Newton: capsule::solve_steady (Newton-Krylov on the midpoint step map, h = 0.5x those
//      steps); when it does not converge the approach goes on to a 4x smaller speed and Newton
//      is tried again (at most kSolveAttempts times);
//   the first level from rest on NB > 8 is solved on NB = 8 first and resampled (coarse start:
//   the long approach from the sphere at cheap evaluations); where that NB = 8 state does not
//   resolve its tips and the fine solve fails or finds compressive tension, the level is solved
//   again along the branch from a lower Ca (climb: Ca lowered by kClimbFactor until the NB = 8
//   state resolves its tips, then pseudo-arclength continuation up to ca).
// correct(p, normal) is the continuation's corrector (the branch follower's and the climb's): the
// map step measured near p's Ca, then Newton on the hyperplane through p normal to `normal`.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "capsule/capsule.h"
#include "capsule/continuation.h"
#include "capsule/steady_solver.h"
#include "control/options.h"
#include "control/record.h"
#include "geometry/mesh.h"

namespace capflow::app {

// A mesh, its capsule and the state on it.
struct Grid {
  std::unique_ptr<geometry::Mesh> mesh;
  std::unique_ptr<capsule::Capsule> cap;
  Eigen::Matrix3Xd x;
  double h_last = 0;  // the last adaptive step size measured on this grid
};
Grid make_grid(const control::ControlOptions& o);

// x on `from`'s mesh carried onto grid g's (geometry::resample_surface), at g's reference volume.
Eigen::Matrix3Xd resampled(const geometry::Mesh& from, const Eigen::Matrix3Xd& x, const Grid& g);

// The health check's node-to-node oscillation indicator of grid g's state.
double oscillation(const Grid& g);

class LevelSolver {
 public:
  static constexpr double kApproachSpeed = 2e-2;  // largest node speed (a G) ending the approach
  static constexpr double kMapStepFactor = 0.5;   // midpoint map step / adaptive steps
  static constexpr double kMaxApproachTime = 400; // simulated time an approach may take
  static constexpr int kSolveAttempts = 3;
  static constexpr int kMinApproachSteps = 10;  // for the controller to reach the stability limit
  static constexpr int kCoarseNb = 8;
  static constexpr double kClimbFactor = 0.75;
  static constexpr int kClimbTries = 4;
  static constexpr int kClimbStates = 4;

  struct Hooks {
    std::function<void(const std::string&)> say;     // a log line
    std::function<void(const std::string&)> status;  // a progress line (at most once a second)
    std::function<void(const control::Record&)> event;
    std::function<void()> between_steps;  // live edits (the options below may change)
    const std::atomic<bool>* stop = nullptr;
  };

  // `options`: the run's (read at every use: live edits of time.tolerance and
  // steady.solve_tolerance apply); `fine`: the control file's mesh and the current state.
  LevelSolver(const control::ControlOptions& options, Grid& fine, Hooks hooks);

  struct Result {
    bool converged = false;        // a steady state: fine.x is it
    bool approach_failed = false;  // the time steps themselves failed (the health check)
    std::string failure;           // why not
    capsule::SteadySolution solution;
    int newton = 0;
    long krylov = 0;
    long evaluations = 0;  // velocity evaluations of this level, on every grid
  };
  // One level. `from_rest`: the first level of a run from rest (the coarse start applies).
  Result solve(double ca, bool from_rest);

  // The continuation's corrector (see above). nullopt when Newton does not converge.
  struct Corrections {
    capsule::SteadySolution last;
    int newton = 0;
    long krylov = 0;
  };
  std::optional<capsule::BranchPoint> correct(const capsule::BranchPoint& p,
                                              const capsule::BranchPoint& normal,
                                              Corrections* k, int* newton);

  double time() const { return t_; }  // simulated time of every approach
  long steps() const { return steps_; }
  bool stopped() const { return hooks_.stop && hooks_.stop->load(); }

 private:
  double approach(Grid& g, double ca, double speed);
  bool solve_on(Grid& g, double ca, capsule::SteadySolution* sol, int* newton, long* krylov);
  bool coarse_start(double ca, int* newton, long* krylov, long* evaluations);
  bool climb(double ca, capsule::SteadySolution* sol, int* newton, long* krylov,
             long* evaluations);
  void measure_step(double ca);
  Grid coarse_grid() const;
  double tau_min() const;
  void say(const std::string& s) const { if (hooks_.say) hooks_.say(s); }

  const control::ControlOptions& opt_;
  Grid& fine_;
  Hooks hooks_;
  double t_ = 0;     // simulated time of all approaches
  double h_ca_ = 0;  // the Ca at which fine_.h_last was measured
  long steps_ = 0;
  double last_progress_ = -1e30;
  bool approach_failed_ = false;
  std::string failure_;
};

}  // namespace capflow::app
