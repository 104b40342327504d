// The Runge-Kutta-Chebyshev stepper (capsule/chebyshev_stepper.h) on model stiff ODEs with known
// solutions: y_k' = -lambda_k (y_k - sin t) + cos t, exact y_k = sin t + c_k exp(-lambda_k t).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "capsule/chebyshev_stepper.h"

using namespace capflow::capsule;

namespace {

Eigen::VectorXd spectrum(double lambda_max, int n) {  // geometric from 1 to lambda_max
  Eigen::VectorXd l(n);
  for (int k = 0; k < n; ++k) l(k) = std::pow(lambda_max, double(k) / (n - 1));
  return l;
}

ChebyshevStepper::Rhs model(const Eigen::VectorXd& lambda) {
  return [lambda](double t, const Eigen::VectorXd& y, Eigen::VectorXd* dydt) {
    *dydt = (-lambda.array() * (y.array() - std::sin(t)) + std::cos(t)).matrix();
  };
}

double exact_error(const Eigen::VectorXd& lambda, double t, const Eigen::VectorXd& y) {
  double e = 0;
  for (int k = 0; k < y.size(); ++k)
    e = std::max(e, std::abs(y(k) - (std::sin(t) + std::exp(-lambda(k) * t))));
  return e;
}

struct Outcome {
  Eigen::VectorXd y;
  long evaluations = 0, steps = 0;
  int max_stages = 0;
};

Outcome integrate(const Eigen::VectorXd& lambda, double tol, double t_end) {
  AdaptiveOptions o;
  o.tolerance = tol;
  o.h_min = 1e-12;
  o.h_max = 1.0;
  ChebyshevStepper st(model(lambda), o);
  st.restart(0.0, Eigen::VectorXd::Ones(lambda.size()), 0.0);
  Outcome r;
  while (st.time() < t_end) {
    st.step(t_end, nullptr, nullptr, &r.y);
    r.max_stages = std::max(r.max_stages, st.last_stages());
    ++r.steps;
  }
  r.evaluations = st.rhs_evaluations();
  return r;
}

}  // namespace

TEST(ChebyshevStepper, StagesCoverTheSpectralRadius) {
  // The fewest stages whose real interval [-beta(s), 0] holds h rho; beta grows as s^2.
  for (double hr : {0.5, 3.0, 40.0, 1e3, 5e3}) {
    const int s = ChebyshevStepper::stages_for(hr, 1.0);
    EXPECT_GE(ChebyshevStepper::real_stability_interval(s), hr) << hr;
    if (s > 2) {
      EXPECT_LT(ChebyshevStepper::real_stability_interval(s - 1), hr) << hr;
    }
  }
  const double b10 = ChebyshevStepper::real_stability_interval(10);
  EXPECT_NEAR(ChebyshevStepper::real_stability_interval(20) / b10, 4.0, 0.3);
}

TEST(ChebyshevStepper, StableOnItsWholeRealInterval) {
  // |R_s(z)| <= 1 on [-beta(s), 0], and < 1 away from z = 0 (the damping).
  for (int s : {2, 3, 5, 10, 25, 60}) {
    const double beta = ChebyshevStepper::real_stability_interval(s);
    double worst = 0;
    for (int k = 1; k <= 2000; ++k) {
      const double z = -beta * k / 2000.0;
      const double r = std::abs(ChebyshevStepper::stability_function(s, z));
      worst = std::max(worst, r);
      if (z < -0.1 * beta) {
        EXPECT_LT(r, 1.0) << "s = " << s << ", z = " << z;
      }
    }
    EXPECT_LE(worst, 1.0 + 1e-12) << "s = " << s;
    // Second order at z -> 0: R = 1 + z + z^2/2 + O(z^3).
    const double z = 1e-3;
    EXPECT_NEAR(ChebyshevStepper::stability_function(s, -z).real(), 1 - z + z * z / 2, 1e-8) << s;
  }
}

TEST(ChebyshevStepper, OneStepMultipliesByTheStabilityFunction) {
  // y' = -0.5 y, one step of h = 1 with the spectral radius pinned, so that the stage count is
  // set by it: the step's stages are the polynomial's recurrence.
  for (double rho : {0.5, 20.0, 400.0, 3000.0}) {
    AdaptiveOptions o;
    o.tolerance = 1e-1;
    o.h_max = 1.0;
    ChebyshevStepper st([](double, const Eigen::VectorXd& y, Eigen::VectorXd* d) { *d = -0.5 * y; },
                        o);
    ChebyshevStepper::History h;
    h.e_prev = 0;
    h.steps = 1;  // not a multiple of kRadiusSteps: rho is not estimated again
    h.rho = rho;
    st.resume(0.0, Eigen::VectorXd::Ones(1), 1.0, h);
    Eigen::VectorXd y;
    const ChebyshevStepper::Step step = st.step(1.0, nullptr, nullptr, &y);
    ASSERT_EQ(step.error_rejections, 0);
    const int s = st.last_stages();
    EXPECT_EQ(s, ChebyshevStepper::stages_for(1.0, rho));
    EXPECT_NEAR(y(0), ChebyshevStepper::stability_function(s, -0.5).real(), 1e-13) << "s = " << s;
  }
}

TEST(ChebyshevStepper, EstimatesTheSpectralRadiusFromAbove) {
  // The power iteration converges to the largest |lambda| and adds its 20 % margin.
  const Eigen::VectorXd lambda = spectrum(4e4, 30);
  AdaptiveOptions o;
  o.tolerance = 1e-6;
  o.h_min = 1e-12;  // the first steps resolve the stiff transient
  ChebyshevStepper st(model(lambda), o);
  st.restart(0.0, Eigen::VectorXd::Ones(lambda.size()), 0.0);
  Eigen::VectorXd y;
  st.step(1.0, nullptr, nullptr, &y);
  EXPECT_GE(st.spectral_radius(), 4e4);
  EXPECT_LE(st.spectral_radius(), 1.25 * 4e4);
}

TEST(ChebyshevStepper, StiffProblemIsAccurateAtAFractionOfAnExplicitPairsCost) {
  // lambda up to 1e5: an explicit pair needs t rho / 3.7 steps (Cash-Karp's real stability
  // interval) of 6 evaluations, 1.6e5 evaluations to t = 1.
  const Eigen::VectorXd lambda = spectrum(1e5, 20);
  const Outcome r = integrate(lambda, 1e-6, 1.0);
  EXPECT_LT(exact_error(lambda, 1.0, r.y), 2e-5);
  const double explicit_evals = 6.0 * 1e5 / 3.7;
  EXPECT_LT(r.evaluations, explicit_evals / 10) << r.evaluations << " evaluations";
  EXPECT_GT(r.max_stages, 10);  // the stiffness is really there
}

TEST(ChebyshevStepper, ErrorFollowsTheTolerance) {
  // A second-order method under local error control: the global error falls with the
  // tolerance (about as tol^(2/3)... tol), and the steps grow as tol^(-1/3).
  const Eigen::VectorXd lambda = spectrum(1e4, 12);
  const Outcome coarse = integrate(lambda, 1e-5, 2.0), fine = integrate(lambda, 1e-8, 2.0);
  const double e_coarse = exact_error(lambda, 2.0, coarse.y);
  const double e_fine = exact_error(lambda, 2.0, fine.y);
  EXPECT_LT(e_coarse, 1e-4);
  EXPECT_LT(e_fine, e_coarse / 30);  // 1000x the tolerance: at least 30x the accuracy
  const double step_ratio = double(fine.steps) / coarse.steps;
  EXPECT_GT(step_ratio, 4.0);  // 1000^(1/3) = 10 for steps set by accuracy alone
  EXPECT_LT(step_ratio, 25.0);
}

TEST(ChebyshevStepper, ResumedFromItsHistoryContinuesBitForBit) {
  const Eigen::VectorXd lambda = spectrum(2e4, 10);
  AdaptiveOptions o;
  o.tolerance = 1e-6;
  ChebyshevStepper a(model(lambda), o);
  a.restart(0.0, Eigen::VectorXd::Ones(lambda.size()), 0.0);
  Eigen::VectorXd y;
  std::vector<double> stops;
  for (int k = 1; k <= 60; ++k) stops.push_back(0.05 * k);
  size_t next = 0;
  auto advance = [&](ChebyshevStepper& st, Eigen::VectorXd* out) {
    while (stops[next] <= st.time()) ++next;
    st.step(stops[next], nullptr, nullptr, out);
  };
  for (int k = 0; k < 37; ++k) advance(a, &y);  // past a spectral-radius estimate
  ChebyshevStepper b(model(lambda), o);
  b.resume(a.time(), y, a.next_step(), a.history());
  const size_t at = next;
  Eigen::VectorXd ya, yb;
  for (int k = 0; k < 40; ++k) {
    next = at;
    advance(a, &ya);
    const size_t after = next;
    next = at;
    advance(b, &yb);
    ASSERT_EQ(next, after);
    ASSERT_EQ(a.time(), b.time()) << k;
    ASSERT_EQ((ya - yb).cwiseAbs().maxCoeff(), 0.0) << k;
  }
}

TEST(ChebyshevStepper, CheckRejectsAStateAndFinishActsOnEveryAcceptedOne) {
  const Eigen::VectorXd lambda = spectrum(1e3, 5);
  AdaptiveOptions o;
  o.tolerance = 1e-6;
  ChebyshevStepper st(model(lambda), o);
  st.restart(0.0, Eigen::VectorXd::Ones(lambda.size()), 0.1);
  int finishes = 0;
  const auto finish = [&](Eigen::VectorXd* y) {
    ++finishes;
    (*y)(0) = std::sin(1.0);  // changes the state: f is evaluated anew
  };
  int refusals = 0;
  std::vector<double> tried;
  const auto check = [&](const Eigen::VectorXd&, double t) -> std::string {
    tried.push_back(t);
    if (refusals < 2) {
      ++refusals;
      return "refused";
    }
    return "";
  };
  Eigen::VectorXd y;
  const ChebyshevStepper::Step s = st.step(1.0, finish, check, &y);
  EXPECT_EQ(s.check_rejections, 2);
  EXPECT_EQ(finishes, 3);
  ASSERT_EQ(tried.size(), 3u);
  EXPECT_NEAR(tried[1], 0.25 * tried[0], 1e-15);  // a refused step is retried at a quarter
  EXPECT_NEAR(tried[2], 0.25 * tried[1], 1e-15);
  EXPECT_EQ(y(0), std::sin(1.0));
  EXPECT_EQ(st.time(), s.t);
}

TEST(ChebyshevStepper, AFailingRightHandSideIsRetriedSmallerThenReported) {
  AdaptiveOptions o;
  o.tolerance = 1e-6;
  o.h_min = 1e-6;
  int calls = 0;
  ChebyshevStepper st(
      [&](double t, const Eigen::VectorXd& y, Eigen::VectorXd* dydt) {
        ++calls;
        if (t > 0.01) throw std::runtime_error("boom");
        *dydt = -y;
      },
      o);
  st.restart(0.0, Eigen::VectorXd::Ones(3), 0.5);
  Eigen::VectorXd y;
  const ChebyshevStepper::Step s = st.step(1.0, nullptr, nullptr, &y);
  EXPECT_GT(s.check_rejections, 0);
  EXPECT_LE(s.t, 0.01 + 1e-12);
  ChebyshevStepper dead([](double, const Eigen::VectorXd&, Eigen::VectorXd*) {
    throw std::runtime_error("boom");
  }, o);
  dead.restart(0.0, Eigen::VectorXd::Ones(3), 0.5);
  EXPECT_THROW(dead.step(1.0, nullptr, nullptr, &y), StepFailure);
}
