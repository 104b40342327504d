// capflow/capsule/adaptive_stepper: explicit Runge-Kutta steps with local error control and a
// step size that finds the stability limit by itself (SUNDIALS ARKODE, ERKStep).
//
// Method: the Cash-Karp 6-stage pair (order 5, embedded order 4; ARKODE_CASH_KARP_6_4_5) with
// ARKODE's explicit Gustafsson step-size controller, relative and absolute tolerance `tolerance`
// on every coordinate (positions are O(1) in units of a). The controller runs as ARKODE's
// custom adaptivity function with ARKODE's formula and constants, on a history this class keeps
// (history()): the same steps as ARKODE's own, and a history that a checkpoint can save. An explicit pair also controls the
// stability limit: beyond it the stiff membrane modes grow and the error estimate rejects the
// step, so the accepted steps settle just inside the limit. Gustafsson's controller is made for
// that regime (fewer rejections than the PI and PID controllers there: docs/performance.md).
//
// What ARKODE does not offer, done here around it:
//   * rejection of a state that passed the error test but fails a check (the caller's Check: a
//     Jacobian sign change, runaway node-to-node oscillation): the step is retried from the
//     state before it at a quarter of its size (ERKStep treats a positive return of the right-
//     hand side as unrecoverable, so a failed velocity evaluation is handled the same way);
//   * a post-step operation (Finish: smoothing, volume correction): when it changes the state,
//     the integrator is restarted from the changed state with the step it proposed;
//   * steps that end exactly on breakpoints (ARKODE's stop time, given anew for every step); the
//     step after one cut short at a breakpoint starts from the last step that was not cut (the
//     controller would grow it from the short one and overshoot the stability limit).
// restart() forgets the controller's error history (as ARKODE's own restart does) and keeps the
// next step size. Between two steps the integrator's whole state is (t, y, next_step(),
// history()): a checkpoint that stores them resumes bit for bit at any step (a signal's), not
// only where the run restarted.
#pragma once

#include <memory>

#include "capsule/integrator.h"

namespace capflow::capsule {

class AdaptiveStepper : public Integrator {
 public:
  AdaptiveStepper(Rhs rhs, const AdaptiveOptions& options);
  ~AdaptiveStepper();
  AdaptiveStepper(const AdaptiveStepper&) = delete;
  AdaptiveStepper& operator=(const AdaptiveStepper&) = delete;

  // restart(h = 0): ARKODE's first-step estimate from the tolerance. history(): the last
  // accepted step's biased error estimate (1 after a restart), the steps taken (ARKODE's nst:
  // the first two use a simpler formula, and only the first grows by more than 20x), the last
  // step not cut at a stop time; rho is not used.
  void restart(double t, const Eigen::VectorXd& y, double h) override;
  void resume(double t, const Eigen::VectorXd& y, double h, const History& history) override;
  History history() const override;
  Step step(double t_stop, const Finish& finish, const Check& check, Eigen::VectorXd* y) override;
  double time() const override { return t_; }
  double next_step() const override;
  void set_tolerance(double tolerance) override;
  double tolerance() const override { return opt_.tolerance; }
  long rhs_evaluations() const override { return rhs_evals_; }

 private:
  struct Arkode;
  void begin(double t, const Eigen::VectorXd& y, double h);  // restart() without the clearing
  std::unique_ptr<Arkode> ark_;
  AdaptiveOptions opt_;
  double t_ = 0;
  double h_free_ = 0;      // the last accepted step not cut at t_stop (or the restart's step)
  double h_pending_ = -1;  // the step given to restart(), before the first step after it
  long rhs_evals_ = 0;
};

}  // namespace capflow::capsule
