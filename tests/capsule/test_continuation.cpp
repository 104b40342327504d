// capsule/continuation: pseudo-arclength continuation on model branches with known answers:
// a fold of y^2 + c = 1 at c = 1 (passed, located, the states beyond it on the other half),
// a branch without fold landing exactly on the end of the range, a corrector that never
// converges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "capsule/continuation.h"

using namespace capflow::capsule;

namespace {

// Newton on { g(y, c) = 0, <normal, (y, c) - predicted> = 0 } for scalar y (n = 1 in the inner
// product). g = y^2 + c - 1 (fold at c = 1, y = 0) or y - c^2.
struct Model {
  bool fold = true;
  double drift = 0;  // on arclength hyperplanes (not Ca = const) the corrector lands this far on in Ca
  int calls = 0;
  double g(double y, double c) const { return fold ? y * y + c - 1 : y - c * c; }
  double gy(double y, double) const { return fold ? 2 * y : 1.0; }
  double gc(double, double c) const { return fold ? 1.0 : -2 * c; }

  std::optional<BranchPoint> correct(const BranchPoint& p, const BranchPoint& n, int* newton) {
    ++calls;
    double y = p.y(0), c = p.ca;
    for (int it = 1; it <= 20; ++it) {
      const double shift = n.y(0) != 0 ? drift : 0;
      const double r1 = g(y, c), r2 = n.y(0) * (y - p.y(0)) + n.ca * (c - p.ca - shift);
      if (std::abs(r1) < 1e-13 && std::abs(r2) < 1e-13) {
        *newton = it - 1;
        BranchPoint out;
        out.y = Eigen::VectorXd::Constant(1, y);
        out.ca = c;
        return out;
      }
      const double a = gy(y, c), b = gc(y, c), d = n.y(0), e = n.ca;
      const double det = a * e - b * d;
      if (det == 0) return std::nullopt;
      y -= (e * r1 - b * r2) / det;
      c -= (-d * r1 + a * r2) / det;
    }
    return std::nullopt;
  }
  BranchCorrector corrector() {
    return [this](const BranchPoint& p, const BranchPoint& n, int* k) { return correct(p, n, k); };
  }
};

BranchPoint point(double y, double c) {
  BranchPoint p;
  p.y = Eigen::VectorXd::Constant(1, y);
  p.ca = c;
  return p;
}

}  // namespace

TEST(Continuation, PassesAndLocatesAFold) {
  Model m;
  ContinuationOptions o;
  o.from = 0.2;
  o.to = 2.0;
  o.step = 0.1;
  o.after_fold = 3;
  ArclengthContinuation k(o, point(-std::sqrt(0.8), 0.2));
  int states = 1, folds = 0;
  double max_dca = 0, prev = 0.2;
  for (;;) {
    const ArclengthContinuation::Status s = k.advance(m.corrector());
    if (s != ArclengthContinuation::Status::State) {
      EXPECT_EQ(s, ArclengthContinuation::Status::Done) << k.why();
      break;
    }
    ++states;
    folds += k.fold_found_now();
    const BranchPoint& p = k.last();
    EXPECT_NEAR(p.y(0) * p.y(0) + p.ca - 1, 0, 1e-12);  // every state is on the branch
    max_dca = std::max(max_dca, std::abs(p.ca - prev));
    prev = p.ca;
    ASSERT_LT(states, 200);
  }
  EXPECT_EQ(folds, 1);
  ASSERT_TRUE(k.fold().has_value());
  // The parabola through three points a step ~0.1 apart: the vertex to O(step^3).
  EXPECT_NEAR(k.fold()->ca, 1.0, 2e-3);
  EXPECT_GT(k.last().y(0), 0);  // on the other half of the branch
  // The predicted change of Ca is at most `step`; at the fold the arclength step (at most 2 step)
  // bounds the corrected one.
  EXPECT_LE(max_dca, 2 * o.step * (1 + 1e-12));
  EXPECT_EQ(states, k.states());
}

TEST(Continuation, LandsOnTheEndOfTheRangeWithoutAFold) {
  Model m;
  m.fold = false;
  ContinuationOptions o;
  o.from = 0.2;
  o.to = 1.0;
  o.step = 0.15;
  ArclengthContinuation k(o, point(0.04, 0.2));
  double prev = 0.2;
  while (k.advance(m.corrector()) == ArclengthContinuation::Status::State) {
    EXPECT_GT(k.last().ca, prev);  // monotone: no fold
    EXPECT_LE(k.last().ca - prev, o.step * (1 + 1e-12));
    EXPECT_NEAR(k.last().y(0), k.last().ca * k.last().ca, 1e-12);
    prev = k.last().ca;
  }
  EXPECT_EQ(k.last().ca, 1.0);
  EXPECT_FALSE(k.fold().has_value());
  EXPECT_EQ(k.advance(m.corrector()), ArclengthContinuation::Status::Done);
}

TEST(Continuation, LandsOnTheRequestedCaValuesOnTheWay) {
  Model m;
  m.fold = false;
  ContinuationOptions o;
  o.from = 0.2;
  o.to = 1.0;
  o.step = 0.15;
  o.at = {0.45, 0.6, 0.61, 2.0};  // 2.0 lies outside the range: never reached
  ArclengthContinuation k(o, point(0.04, 0.2));
  std::vector<double> seen;
  while (k.advance(m.corrector()) == ArclengthContinuation::Status::State)
    seen.push_back(k.last().ca);
  for (double a : {0.45, 0.6, 0.61, 1.0})
    EXPECT_EQ(std::count(seen.begin(), seen.end(), a), 1) << a;
  EXPECT_EQ(seen.back(), 1.0);
}

// A corrector may end its state beyond its prediction (capflow steady's corrector measures the
// branch in its own scaled norm): here it lands on the arclength hyperplane shifted forward by
// 0.013 in Ca. A state that passes a requested Ca is not taken; the step lands on that Ca.
TEST(Continuation, LandsOnRequestedCaValuesTheCorrectorWouldPass) {
  for (bool up : {true, false}) {
    Model m;
    m.fold = false;
    m.drift = up ? 0.013 : -0.013;
    ContinuationOptions o;
    o.from = up ? 0.2 : 1.0;
    o.to = up ? 1.0 : 0.2;
    o.step = 0.05;
    for (int k = 3; k <= 9; ++k) o.at.push_back(0.1 * k);
    ArclengthContinuation k(o, point(o.from * o.from, o.from));
    std::vector<double> seen;
    while (k.advance(m.corrector()) == ArclengthContinuation::Status::State)
      seen.push_back(k.last().ca);
    for (double a : o.at) EXPECT_EQ(std::count(seen.begin(), seen.end(), a), 1) << a << " " << up;
    EXPECT_EQ(seen.back(), o.to);
  }
}

TEST(Continuation, DecreasingRangesAndLiveEditsOfTheEnd) {
  Model m;
  m.fold = false;
  ContinuationOptions o;
  o.from = 1.0;
  o.to = 0.3;
  o.step = 0.1;
  ArclengthContinuation k(o, point(1.0, 1.0));
  ASSERT_EQ(k.advance(m.corrector()), ArclengthContinuation::Status::State);
  EXPECT_NEAR(k.last().ca, 0.9, 1e-12);  // the first step is a natural one
  k.set_range(0.75, 0.1, 3, {});         // the range shortened while the branch goes on
  while (k.advance(m.corrector()) == ArclengthContinuation::Status::State) {
  }
  EXPECT_EQ(k.last().ca, 0.75);
}

TEST(Continuation, ACorrectorThatNeverConvergesEndsTheBranch) {
  ContinuationOptions o;
  o.from = 0.2;
  o.to = 1.0;
  o.step = 0.1;
  ArclengthContinuation k(o, point(0.0, 0.2));
  int calls = 0;
  const BranchCorrector never = [&](const BranchPoint&, const BranchPoint&, int*) {
    ++calls;
    return std::optional<BranchPoint>();
  };
  EXPECT_EQ(k.advance(never), ArclengthContinuation::Status::Stuck);
  EXPECT_EQ(calls, 7);  // 0.1, 0.05, ..., 0.1/64; then the step is below 0.1/64
  EXPECT_NE(k.why().find("Ca = 0.2"), std::string::npos) << k.why();
  EXPECT_EQ(k.states(), 1);
}
