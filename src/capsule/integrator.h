// capflow/capsule/integrator: what the adaptive time integrators share (AdaptiveStepper: an
// explicit pair at its stability limit; ChebyshevStepper: stabilized Runge-Kutta-Chebyshev),
// so that app::TimeStepper drives either. Between two steps an integrator's whole state is
// (t, y, next_step(), history()): a checkpoint that stores them resumes bit for bit.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <stdexcept>
#include <string>

namespace capflow::capsule {

struct AdaptiveOptions {
  double tolerance = 1e-6;  // local error tolerance (relative and absolute), [1e-10, 1e-2]
  double h_min = 1e-6;      // a step that must fall below this fails (StepFailure)
  double h_max = 0.1;
};

// The step size fell below h_min, or a state kept failing its check: the message says why.
class StepFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Integrator {
 public:
  // dy/dt = rhs(t, y); rhs may throw (the step is then retried smaller).
  using Rhs = std::function<void(double t, const Eigen::VectorXd& y, Eigen::VectorXd* dydt)>;
  // Post-step operation on an accepted state (may change it).
  using Finish = std::function<void(Eigen::VectorXd* y)>;
  // "" for a healthy state at time t, otherwise why it is not.
  using Check = std::function<std::string(const Eigen::VectorXd& y, double t)>;

  // The controller's memory between steps (each integrator says what its fields mean).
  struct History {
    double e_prev = 1;  // the last accepted step's error estimate
    long steps = 0;     // accepted steps
    double h_free = 0;  // the last accepted step not cut at a stop time
    double rho = 0;     // ChebyshevStepper: the spectral radius in use (0: none)
  };
  struct Step {
    double t = 0;              // the time reached (t_stop exactly when the step was cut there)
    double h = 0;              // the step taken
    int error_rejections = 0;  // attempts refused by the error test
    int check_rejections = 0;  // attempts refused by `check` or a failed right-hand side
  };
  virtual ~Integrator() = default;

  // Starts (again) from (t, y); the first step is h (0: the integrator's own estimate).
  virtual void restart(double t, const Eigen::VectorXd& y, double h) = 0;
  // Starts from (t, y) as a run that saved (h, history) there goes on. std::invalid_argument
  // for a malformed history.
  virtual void resume(double t, const Eigen::VectorXd& y, double h, const History& history) = 0;
  virtual History history() const = 0;
  // One accepted step from the current state, ending at t_stop or before; *y receives the state
  // (after `finish`). `check` may refuse a state (the step is retried at a quarter of its size),
  // and a throwing rhs is retried the same way. Throws StepFailure when no step above h_min
  // passes.
  virtual Step step(double t_stop, const Finish& finish, const Check& check,
                    Eigen::VectorXd* y) = 0;
  virtual double time() const = 0;
  // The step the controller proposes next.
  virtual double next_step() const = 0;
  // A new tolerance applies from the next step (the controller history is kept).
  virtual void set_tolerance(double tolerance) = 0;
  virtual double tolerance() const = 0;
  virtual long rhs_evaluations() const = 0;
};

}  // namespace capflow::capsule
