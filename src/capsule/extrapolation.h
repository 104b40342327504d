// capflow/capsule/extrapolation: one-mode extrapolation of a slow approach to a steady state.
//
// Near a stable steady state x* the time-stepped states relax as x(t) = x* + sum_k v_k e^{-t/tau_k}.
// Once the faster modes have died out, one slow mode is left; from three states a time Delta
// apart, x0, x1, x2, with differences d1 = x1 - x0 and d2 = x2 - x1 = q d1 (q = e^{-Delta/tau}),
// the limit is x* = x2 + d2 q / (1 - q) (Aitken's delta-squared process applied to the whole
// state, with one ratio q fitted by least squares: q = <d1, d2> / <d1, d1>).
// The result is a starting guess, not a steady state: a run from it must show that the
// dynamics stay there (the steady test of the run). The relative residual |d2 - q d1| / |d2|
// says how well one mode describes the three states; extrapolate_one_mode refuses q outside
// (0, q_max] and residuals above the caller's bound.
#pragma once

#include <Eigen/Dense>
#include <stdexcept>

namespace capflow::capsule {

struct OneModeExtrapolation {
  Eigen::Matrix3Xd x;    // the extrapolated state x2 + d2 q / (1 - q)
  double q = 0;          // the fitted ratio per interval
  double residual = 0;   // |d2 - q d1| / |d2| (0 for an exact single mode)
  double factor = 0;     // q / (1 - q), the multiple of d2 added to x2
};

struct ExtrapolationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws ExtrapolationError when the shapes differ, when the states do not move (d1 = 0), when q
// is not in (0, q_max] (not a monotone decaying approach, or too slow to extrapolate safely:
// the factor q/(1-q) amplifies the residual), or when residual > max_residual.
OneModeExtrapolation extrapolate_one_mode(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1,
                                          const Eigen::Matrix3Xd& x2, double max_residual,
                                          double q_max = 0.98);

}  // namespace capflow::capsule
