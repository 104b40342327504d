// capflow/capsule/chebyshev_stepper: stabilized explicit steps for stiff membranes - the
// second-order Runge-Kutta-Chebyshev method (RKC) of Sommeijer, Shampine & Verwer (J. Comput.
// Appl. Math. 88, 1998, 315-326), with its error estimate, step-size controller and nonlinear
// power iteration for the spectral radius.
//
// Why: the membrane's stiff modes are dissipative, with eigenvalues of df/dy down to -rho ~
// C/(Ca dx) for the elastic load (~ Eb/(Ca dx^3) with bending). An explicit pair's step is
// bounded by ~3.7/rho (Cash-Karp) at 6 evaluations a step; an s-stage Chebyshev step is stable
// on a real interval growing as s^2, so s ~ sqrt(h rho) evaluations buy a step of h. The
// collocated membrane operator is not symmetric, though: part of its spectrum is complex
// (measured on a red cell at NE 10 NB 12: -3040 +- 1985i beside rho = 1.8e4), and the classical
// damping's thin strip around the real axis cannot hold it. This stepper uses a strong damping
// (eps = 16: real interval 0.29 s^2, a wide strip, stiff transients damped ~140x a step), and the
// step controller finds the remaining limit as the explicit pair's does, by its error test.
// The number of stages is the fewest whose real interval holds h rho.
// SUNDIALS ships this method (ARKODE LSRKStep) only from 7.2; Debian 12 packages 6.4.
//
// The same contract as AdaptiveStepper: `finish` (smoothing, volume correction) acts on every
// accepted state, `check` (health) can refuse it (the step is retried at a quarter of its size),
// steps end exactly on t_stop, and a failed velocity evaluation is retried smaller. Between two
// steps the whole state is (t, y, next_step(), history()): the spectral radius is estimated anew
// every kRadiusSteps steps counted by history().steps (and after a rejection or a restart),
// always from the same start vector (node-to-node alternation about y), so a run resumed at any
// step continues bit for bit.
#pragma once

#include <Eigen/Dense>
#include <complex>

#include "capsule/integrator.h"

namespace capflow::capsule {

class ChebyshevStepper : public Integrator {
 public:
  // The damping eps (w0 = 1 + eps/s^2). The classical 2/13 (rkc.f) keeps the longest real
  // interval, 0.65 s^2, around a strip so thin that the membrane's complex eigenvalues leave it:
  // at NE 10 NB 12 the red cell's Jacobian has eigenvalues -3040 +- 1985i beside rho = 1.8e4,
  // and |R(h J)| <= 1 holds only up to h = 1.2e-3 whatever s (benchmarks/capsule/
  // membrane_spectrum). eps = 16 widens the strip (h up to 7e-3 at s = 25) and damps stiff
  // transients by 1/T_s(w0) ~ 1/cosh(sqrt(2 eps)) ~ 1/140 a step, at 0.29 s^2 of real interval.
  // On that cell from t = 0 to 2 it took 9931 velocity evaluations; a first version with the
  // classical damping (and growth 10) 17831.
  static constexpr double kDamping = 16.0;
  static constexpr int kRadiusSteps = 25;  // steps between two spectral-radius estimates
  static constexpr int kMaxStages = 400;   // a step needing more is shortened

  ChebyshevStepper(Rhs rhs, const AdaptiveOptions& options);

  // Starts (again) from (t, y); the first step is h (0: an estimate from f(y) and the
  // tolerance). The controller's memory and the spectral radius are dropped.
  void restart(double t, const Eigen::VectorXd& y, double h) override;
  void resume(double t, const Eigen::VectorXd& y, double h, const History& history) override;
  // e_prev: the last accepted step's error (0: none since the restart), steps, h_free: the last
  // accepted step not cut at a stop time, rho: the spectral radius in use (0: estimate anew).
  History history() const override { return hist_; }
  Step step(double t_stop, const Finish& finish, const Check& check, Eigen::VectorXd* y) override;
  double time() const override { return t_; }
  double next_step() const override { return h_next_; }
  void set_tolerance(double tolerance) override;
  double tolerance() const override { return opt_.tolerance; }
  long rhs_evaluations() const override { return evals_; }
  int last_stages() const { return last_stages_; }
  double spectral_radius() const { return hist_.rho; }

  // The stages one step of size h takes at spectral radius rho: the fewest whose real stability
  // interval [-beta, 0] holds h rho.
  static int stages_for(double h, double rho);
  // beta(s) of the s-stage damped method: 0.29 s^2 at eps = 16 (0.65 s^2 at the classical 2/13).
  static double real_stability_interval(int s, double eps = kDamping);
  // R_s(z) = a + b T_s(w0 + w1 z): one s-stage step multiplies y' = lambda y by R_s(h lambda)
  // (eps: the damping; other values for studies of the choice).
  static std::complex<double> stability_function(int s, std::complex<double> z,
                                                 double eps = kDamping);

 private:
  void f(double t, const Eigen::VectorXd& y, Eigen::VectorXd* dydt);
  // The spectral radius of df/dy at (t_, y_), by a nonlinear power iteration started from f0.
  double estimate_radius();
  // One RKC step of size h with s stages from (t_, y_, f_); *y1 receives the end state.
  void rkc(double h, int s, Eigen::VectorXd* y1);
  // The weighted RMS norm of the embedded error estimate of the step y_ -> y1.
  double error_norm(double h, const Eigen::VectorXd& y1, const Eigen::VectorXd& f1) const;

  Rhs rhs_;
  AdaptiveOptions opt_;
  double t_ = 0;
  Eigen::VectorXd y_, f_;  // the accepted state and f there
  bool f_valid_ = false;
  double h_next_ = 0;
  History hist_;
  long evals_ = 0;
  int last_stages_ = 0;
  Eigen::VectorXd yjm1_, yjm2_, work_;  // stage buffers
};

}  // namespace capflow::capsule
