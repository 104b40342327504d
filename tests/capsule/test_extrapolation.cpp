// One-mode (Aitken) extrapolation of a slow approach to a steady state: exact on a single
// exponential mode, second-order error from a faster second mode, refusals for states that are
// not a monotone decay.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capsule/extrapolation.h"

using capflow::capsule::ExtrapolationError;
using capflow::capsule::extrapolate_one_mode;
using Eigen::Matrix3Xd;

namespace {
Matrix3Xd random_state(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Matrix3Xd x(3, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < 3; ++i) x(i, j) = g(rng);
  return x;
}
}  // namespace

TEST(OneModeExtrapolation, ExactOnOneExponentialMode) {
  const Matrix3Xd xs = random_state(200, 1), v = random_state(200, 2);
  const double tau = 24.0, dt = 2.5, t0 = 46.0;
  auto x = [&](double t) -> Matrix3Xd { return xs + std::exp(-t / tau) * v; };
  const auto r = extrapolate_one_mode(x(t0), x(t0 + dt), x(t0 + 2 * dt), 1e-8);
  EXPECT_NEAR(r.q, std::exp(-dt / tau), 1e-13);
  EXPECT_LT(r.residual, 1e-10);
  // The remaining distance e^{-t/tau}|v| ~ 0.12 |v| is removed to round-off.
  EXPECT_LT((r.x - xs).norm() / xs.norm(), 1e-12);
}

TEST(OneModeExtrapolation, FasterSecondModeLeavesItsOwnSmallError) {
  // x = xs + a e^{-t/tau1} v1 + b e^{-t/tau2} v2 with tau2 << tau1: the error of the
  // extrapolated state is of the size of the second mode's part, far below the slow remainder.
  const Matrix3Xd xs = random_state(150, 3), v1 = random_state(150, 4), v2 = random_state(150, 5);
  const double tau1 = 24.0, tau2 = 1.0, dt = 2.5;
  auto x = [&](double t) -> Matrix3Xd {
    return xs + std::exp(-t / tau1) * v1 + 1e-3 * std::exp(-t / tau2) * v2;
  };
  const double t0 = 10.0;
  const auto r = extrapolate_one_mode(x(t0), x(t0 + dt), x(t0 + 2 * dt), 0.05);
  const double before = (x(t0 + 2 * dt) - xs).norm();
  const double after = (r.x - xs).norm();
  EXPECT_LT(after, 1e-3 * before);
  EXPECT_GT(r.residual, 0.0);
  EXPECT_NEAR(r.factor, r.q / (1 - r.q), 1e-15);
}

TEST(OneModeExtrapolation, RefusesStatesThatAreNotAMonotoneDecay) {
  const Matrix3Xd a = random_state(50, 6), v = random_state(50, 7), w = random_state(50, 8);
  // Growing (q > 1), oscillating (q < 0), standing still.
  EXPECT_THROW(extrapolate_one_mode(a, a + v, a + 2.5 * v, 0.05), ExtrapolationError);
  EXPECT_THROW(extrapolate_one_mode(a, a + v, a + 0.5 * v, 0.05), ExtrapolationError);
  // Too slow (q = 0.99 above the default bound 0.98: the factor q/(1-q) = 99 would amplify
  // any residual).
  EXPECT_THROW(extrapolate_one_mode(a, a + v, a + 1.99 * v, 0.05), ExtrapolationError);
  EXPECT_THROW(extrapolate_one_mode(a, a + v, a, 0.05), ExtrapolationError);
  EXPECT_THROW(extrapolate_one_mode(a, a, a + v, 0.05), ExtrapolationError);
  // Two unrelated changes: one mode does not describe them.
  EXPECT_THROW(extrapolate_one_mode(a, a + v, a + v + 0.5 * w, 0.05), ExtrapolationError);
  // Different node counts.
  EXPECT_THROW(extrapolate_one_mode(a, a + v, random_state(49, 9), 0.05), ExtrapolationError);
  // Within bounds it goes through.
  EXPECT_NO_THROW(extrapolate_one_mode(a, a + v, a + v + 0.5 * v, 0.05));
}
