// The adaptive stepper (capsule/adaptive_stepper.h) on a model stiff ODE whose stability limit
// is known: y_k' = -lambda_k (y_k - sin t) + cos t, exact solution sin t + c_k exp(-lambda_k t).
// Once the transient has decayed the error estimate alone would allow large steps; the fastest
// mode (lambda = 2000) then limits them to the Cash-Karp method's real stability interval,
// computed here from the method's Butcher table: R(z) = 1 + z b^T (I - z A)^-1 1.
#include <cstdio>  // arkode_butcher.h uses FILE without including it

#include <arkode/arkode_butcher_erk.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "capsule/adaptive_stepper.h"

using namespace capflow::capsule;

namespace {

const Eigen::Vector3d kLambda(2000.0, 50.0, 1.0);

void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd* dydt) {
  dydt->resize(y.size());
  for (int i = 0; i < y.size(); ++i) (*dydt)[i] = -kLambda[i] * (y[i] - std::sin(t)) + std::cos(t);
}

// |R(z)| of the Cash-Karp 5th-order solution for real z.
double amplification(double z) {
  ARKodeButcherTable b = ARKodeButcherTable_LoadERK(ARKODE_CASH_KARP_6_4_5);
  const int s = b->stages;
  Eigen::MatrixXd A(s, s);
  Eigen::VectorXd w(s);
  for (int i = 0; i < s; ++i) {
    w(i) = b->b[i];
    for (int j = 0; j < s; ++j) A(i, j) = b->A[i][j];
  }
  ARKodeButcherTable_Free(b);
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(s, s) - z * A;
  return std::abs(1.0 + z * w.dot(M.lu().solve(Eigen::VectorXd::Ones(s))));
}

// The left end of the real stability interval: |R(z)| <= 1 on [-boundary, 0].
double stability_boundary() {
  double lo = 1.0, hi = 1.0;
  while (amplification(-hi) <= 1.0) hi *= 1.5;
  for (int k = 0; k < 80; ++k) {
    const double mid = 0.5 * (lo + hi);
    (amplification(-mid) <= 1.0 ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

TEST(AdaptiveStepper, StepsSettleAtTheStabilityLimitWithoutOscillating) {
  const double boundary = stability_boundary();
  ASSERT_GT(boundary, 2.0);  // an explicit 6-stage method: about 3.2-3.6
  ASSERT_LT(boundary, 6.0);
  AdaptiveOptions o;
  o.tolerance = 1e-6;
  o.h_min = 1e-9;
  AdaptiveStepper st(rhs, o);
  const Eigen::VectorXd y0 = Eigen::Vector3d(1.0, 1.0, 1.0);
  st.restart(0.0, y0, 0.0);
  Eigen::VectorXd y;
  std::vector<double> h_late;
  long accepted = 0, rejected = 0;
  const double t_end = 3.0;
  while (st.time() < t_end) {
    const AdaptiveStepper::Step s = st.step(t_end, nullptr, nullptr, &y);
    if (s.t > 0.5 && s.t < t_end) {  // the transient of the stiff mode is long gone
      h_late.push_back(s.h * kLambda(0) / boundary);
      ++accepted;
      rejected += s.error_rejections;
    }
  }
  EXPECT_EQ(st.time(), t_end);
  std::sort(h_late.begin(), h_late.end());
  const double median = h_late[h_late.size() / 2];
  std::printf("boundary %.4f, median h lambda / boundary %.3f, max %.3f, %ld rejected of %ld\n",
              boundary, median, h_late.back(), rejected, accepted);
  // The steps sit just inside the stability limit ...
  EXPECT_GT(median, 0.6) << "median h lambda / boundary";
  EXPECT_LT(median, 1.05) << "median h lambda / boundary";
  EXPECT_LT(h_late.back(), 1.5);
  // ... and the controller does not cycle between growing past it and rejecting.
  EXPECT_LT(static_cast<double>(rejected) / accepted, 0.15)
      << rejected << " rejected of " << accepted;
  // The solution stays accurate (and bounded) throughout.
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(y(k), std::sin(t_end) + std::exp(-kLambda(k) * t_end), 1e-5) << "component " << k;
}

TEST(AdaptiveStepper, StepsEndExactlyOnTheStopTime) {
  AdaptiveStepper st(rhs, {});
  st.restart(0.0, Eigen::Vector3d(0.0, 0.0, 0.0), 0.0);
  Eigen::VectorXd y;
  for (const double stop : {0.0123, 0.1, 0.3, 0.7}) {
    AdaptiveStepper::Step s;
    do s = st.step(stop, nullptr, nullptr, &y);
    while (s.t < stop);
    EXPECT_EQ(s.t, stop);
    EXPECT_EQ(st.time(), stop);
  }
}

TEST(AdaptiveStepper, AFailedCheckRetriesTheStepSmallerOrFails) {
  AdaptiveOptions o;
  o.h_min = 1e-6;
  AdaptiveStepper st(rhs, o);
  st.restart(0.0, Eigen::Vector3d(0.0, 0.0, 0.0), 0.0);
  Eigen::VectorXd y;
  while (st.time() < 0.2) st.step(0.2, nullptr, nullptr, &y);
  // A check that refuses any state reached by a step longer than 2e-4.
  double t_before = st.time();
  const auto short_steps = [&](const Eigen::VectorXd&, double t) {
    return t - t_before > 2e-4 ? std::string("too far") : std::string();
  };
  const AdaptiveStepper::Step s = st.step(1.0, nullptr, short_steps, &y);
  EXPECT_GE(s.check_rejections, 1);
  EXPECT_LE(s.h, 2e-4);
  EXPECT_NEAR(y(2), std::sin(s.t), 1e-6);
  // A check that refuses everything: the step fails below h_min, the state stays where it was.
  t_before = st.time();
  const auto never = [](const Eigen::VectorXd&, double) { return std::string("never healthy"); };
  try {
    st.step(1.0, nullptr, never, &y);
    FAIL() << "no StepFailure";
  } catch (const StepFailure& e) {
    EXPECT_NE(std::string(e.what()).find("never healthy"), std::string::npos) << e.what();
  }
  EXPECT_EQ(st.time(), t_before);
  // A right-hand side that throws is retried the same way and reported.
  AdaptiveStepper bad(
      [](double t, const Eigen::VectorXd& yy, Eigen::VectorXd* d) {
        if (t > 0.05) throw std::runtime_error("Jacobian sign");
        rhs(t, yy, d);
      },
      o);
  bad.restart(0.0, Eigen::Vector3d(0.0, 0.0, 0.0), 0.0);
  try {
    for (int k = 0; k < 10000; ++k) bad.step(1.0, nullptr, nullptr, &y);
    FAIL() << "no StepFailure";
  } catch (const StepFailure& e) {
    EXPECT_NE(std::string(e.what()).find("Jacobian sign"), std::string::npos) << e.what();
  }
  EXPECT_LE(bad.time(), 0.05);
}

TEST(AdaptiveStepper, AnErrorTestFailureSaysWhy) {
  // y' = y^2, y(0) = 1 blows up at t = 1: the error test fails down to h_min before it.
  AdaptiveOptions o;
  o.h_min = 1e-6;
  AdaptiveStepper st(
      [](double, const Eigen::VectorXd& y, Eigen::VectorXd* d) { *d = y.array().square(); }, o);
  st.restart(0.0, Eigen::VectorXd::Ones(1), 0.0);
  Eigen::VectorXd y;
  try {
    for (int k = 0; k < 100000; ++k) st.step(2.0, nullptr, nullptr, &y);
    FAIL() << "no StepFailure";
  } catch (const StepFailure& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find("()"), std::string::npos) << what;
    EXPECT_NE(what.find("error test"), std::string::npos) << what;
  }
  EXPECT_LT(st.time(), 1.0);
}

TEST(AdaptiveStepper, AFinishThatChangesTheStateRestartsFromIt) {
  // A projection after every step (like the volume correction): y_2 is kept at sin t exactly.
  AdaptiveStepper st(rhs, {});
  st.restart(0.0, Eigen::Vector3d(0.0, 0.0, 0.0), 0.0);
  Eigen::VectorXd y;
  double t_last = 0;
  const auto project = [&](Eigen::VectorXd* v) { (*v)(2) = 42.0; };
  const AdaptiveStepper::Step s = st.step(0.5, project, nullptr, &y);
  EXPECT_EQ(y(2), 42.0);
  t_last = s.t;
  // The next step continues from the projected state: y_2' = -(42 - sin t) + cos t < 0.
  const AdaptiveStepper::Step s2 = st.step(0.5, nullptr, nullptr, &y);
  EXPECT_GT(s2.t, t_last);
  EXPECT_LT(y(2), 42.0);
  EXPECT_GT(y(2), 41.0);
}
