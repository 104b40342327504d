// The colour-range rule (render/color_range.h): the default range holds every frame's values
// and never shrinks, with round bounds; "frame" follows each frame; a fixed range flags the
// values beyond it; diverging maps get symmetric ranges; the ticks are multiples of a 1-2-5
// step inside the range.
#include "render/color_range.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using capflow::render::ColorRange;
using capflow::render::RangeMode;
using capflow::render::round_ticks;
using capflow::render::fixed_range_problem;
using capflow::render::tick_step;

namespace {

// v is k * 10^p with k in {1, 2, 5} (to rounding)
bool one_two_five(double v) {
  const double p = std::pow(10.0, std::floor(std::log10(v) + 1e-12));
  const double k = v / p;
  return std::abs(k - 1) < 1e-9 || std::abs(k - 2) < 1e-9 || std::abs(k - 5) < 1e-9;
}

bool multiple_of(double v, double step) {
  return std::abs(v / step - std::round(v / step)) < 1e-9;
}

}  // namespace

TEST(ColorRange, GrowsToHoldEveryFrameAndNeverShrinks) {
  ColorRange r(RangeMode::Grow, false);
  std::mt19937 g(7);
  std::uniform_real_distribution<double> u(-1, 1);
  double all_lo = 1e300, all_hi = -1e300, prev_lo = 0, prev_hi = 0;
  int changes = 0;
  for (int f = 0; f < 400; ++f) {
    // a tension that rises over the movie with noise, and a frame that dips
    const double c = 0.01 * f, lo = c - 0.5 + 0.1 * u(g), hi = c + 0.5 + 0.1 * u(g);
    r.update(lo, hi);
    all_lo = std::min(all_lo, lo);
    all_hi = std::max(all_hi, hi);
    EXPECT_LE(r.lo(), all_lo);
    EXPECT_GE(r.hi(), all_hi);
    EXPECT_FALSE(r.under() || r.over());
    if (f > 0) {
      EXPECT_LE(r.lo(), prev_lo);
      EXPECT_GE(r.hi(), prev_hi);
      changes += r.lo() != prev_lo || r.hi() != prev_hi;
    }
    // round bounds: multiples of the 1-2-5 step of the span
    const double step = tick_step(r.hi() - r.lo());
    EXPECT_TRUE(one_two_five(step)) << step;
    EXPECT_TRUE(multiple_of(r.lo(), step)) << r.lo() << " step " << step;
    EXPECT_TRUE(multiple_of(r.hi(), step)) << r.hi() << " step " << step;
    prev_lo = r.lo();
    prev_hi = r.hi();
  }
  EXPECT_LT(changes, 60);  // a few steps, not every frame
  EXPECT_GT(changes, 0);
}

TEST(ColorRange, AFlatFirstFrameIsOnlyAPlaceholderForGrow) {
  // A red cell at rest in its reference shape: bending energy 0 everywhere (placeholder range
  // [-0.6, 0.6]); while frames stay flat the placeholder stays; the first frame with a spread
  // (0 to 0.0031) sets a range of its own scale holding every value drawn, [0, 0.004]; from
  // then on the range only grows.
  ColorRange r(RangeMode::Grow, false);
  r.update(0, 0);
  EXPECT_DOUBLE_EQ(r.lo(), -0.6);
  EXPECT_DOUBLE_EQ(r.hi(), 0.6);
  r.update(0, 0);
  EXPECT_DOUBLE_EQ(r.lo(), -0.6);
  r.update(0, 0.0031);
  EXPECT_DOUBLE_EQ(r.lo(), 0);
  EXPECT_DOUBLE_EQ(r.hi(), 0.004);
  r.update(0.001, 0.002);
  EXPECT_DOUBLE_EQ(r.lo(), 0);
  EXPECT_DOUBLE_EQ(r.hi(), 0.004);
  r.update(-0.001, 0.002);  // grows, never back to a placeholder
  EXPECT_LE(r.lo(), -0.001);
  EXPECT_DOUBLE_EQ(r.hi(), 0.004);
  // a flat frame at 2 then a spread above it: the range holds the 2 as well
  ColorRange s(RangeMode::Grow, false);
  s.update(2, 2);
  s.update(2.5, 3);
  EXPECT_LE(s.lo(), 2);
  EXPECT_GE(s.hi(), 3);
  EXPECT_GT(s.lo(), 1.5);  // not the placeholder's [1, 3]
}

TEST(ColorRange, FrameModeFollowsEachFrame) {
  ColorRange r(RangeMode::Frame, false);
  r.update(0.0, 4.3);
  EXPECT_EQ(r.lo(), 0.0);
  EXPECT_NEAR(r.hi(), 5.0, 1e-12);  // 4.3 rounded up to the step 1
  r.update(1.54, 1.6);
  EXPECT_NEAR(r.lo(), 1.54, 1e-12);
  EXPECT_NEAR(r.hi(), 1.6, 1e-12);
}

TEST(ColorRange, ConstantFieldsAndDivergingMaps) {
  ColorRange c(RangeMode::Grow, false);
  c.update(0.0, 0.0);  // a sphere at rest: [-0.5, 0.5] rounded out to the step 0.2
  EXPECT_NEAR(c.lo(), -0.6, 1e-12);
  EXPECT_NEAR(c.hi(), 0.6, 1e-12);
  ColorRange s(RangeMode::Grow, true);
  s.update(-0.2, 1.3);
  EXPECT_EQ(s.lo(), -s.hi());
  EXPECT_GE(s.hi(), 1.3);
  s.update(-2.1, 0.5);
  EXPECT_EQ(s.lo(), -s.hi());
  EXPECT_GE(s.hi(), 2.1);
}

TEST(ColorRange, FixedRangeFlagsValuesBeyondIt) {
  ColorRange r(RangeMode::Fixed, false, 0.0, 2.0);
  r.update(0.5, 1.5);
  EXPECT_FALSE(r.under() || r.over());
  r.update(-0.1, 2.5);
  EXPECT_TRUE(r.under());
  EXPECT_TRUE(r.over());
  EXPECT_EQ(r.lo(), 0.0);
  EXPECT_EQ(r.hi(), 2.0);
  r.update(0.1, 2.5);
  EXPECT_FALSE(r.under());
  EXPECT_TRUE(r.over());
}

TEST(ColorRange, TicksAreRoundAndInside) {
  for (const auto& [lo, hi] : {std::pair{0.0603, 0.47}, std::pair{-0.5, 0.5}, std::pair{1.54, 4.31},
                               std::pair{-3.2e-4, 7.7e-3}, std::pair{0.0, 1.0},
                               std::pair{99.2, 99.3}, std::pair{-12.0, -3.0}}) {
    const std::vector<double> t = round_ticks(lo, hi);
    ASSERT_GE(t.size(), 2u) << lo << " " << hi;
    EXPECT_LE(t.size(), 11u) << lo << " " << hi;
    const double step = t[1] - t[0];
    EXPECT_TRUE(one_two_five(step)) << step;
    for (double v : t) {
      EXPECT_GE(v, lo - 1e-9 * (hi - lo));
      EXPECT_LE(v, hi + 1e-9 * (hi - lo));
      EXPECT_TRUE(multiple_of(v, step)) << v;
    }
  }
  const std::vector<double> t = round_ticks(1.54, 4.31);
  EXPECT_EQ(t, (std::vector<double>{2, 3, 4}));
}

TEST(ColorRange, NonFiniteFramesLeaveTheRangeAlone) {
  ColorRange r(RangeMode::Grow, false);
  r.update(0.0, 4.3);
  const double lo = r.lo(), hi = r.hi();
  r.update(std::nan(""), 1.0);
  r.update(0.0, INFINITY);
  EXPECT_EQ(r.lo(), lo);
  EXPECT_EQ(r.hi(), hi);
  EXPECT_TRUE(round_ticks(-INFINITY, 1.0).empty());
  EXPECT_TRUE(round_ticks(0.0, std::nan("")).empty());
}

// Milestone 17: ranges a double cannot resolve. round_ticks used to loop forever on them (k += 1
// stops changing k at 1e16, an infinite span makes no ticks and retries), which hung a run at
// its first frame and `capflow render --range`.
TEST(ColorRange, TicksAlwaysEndAndStayFew) {
  const double big = 1e16;
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {big, big + 2},
           {-1e308, 1e308},
           {-1e308, -1e307},
           {0, 1e308},
           {1e-300, 2e-300},
           {5e-324, 1e-323},
           {1e15, 1e15 + 0.5},
           {-INFINITY, 1},
           {0, NAN}}) {
    const std::vector<double> t = round_ticks(lo, hi);
    EXPECT_LE(t.size(), 1001u) << lo << " " << hi;
    for (double v : t) EXPECT_TRUE(std::isfinite(v)) << lo << " " << hi;
  }
  // unresolvable: the two ends
  EXPECT_EQ(round_ticks(big, big + 2), (std::vector<double>{big, big + 2}));
  EXPECT_EQ(round_ticks(-1e308, 1e308), (std::vector<double>{-1e308, 1e308}));
  // ordinary ranges unchanged
  EXPECT_EQ(round_ticks(0, 1), (std::vector<double>{0, 1 * 0.2, 2 * 0.2, 3 * 0.2, 4 * 0.2, 5 * 0.2}));
}

TEST(ColorRange, AFixedRangeMustBeResolvable) {
  EXPECT_EQ(fixed_range_problem(0, 2), "");
  EXPECT_EQ(fixed_range_problem(-1e12, 1e12), "");
  EXPECT_NE(fixed_range_problem(1e16, 1e16 + 2).find("must be finite and within"),
            std::string::npos);
  EXPECT_NE(fixed_range_problem(1e11, 1e11 + 1e-3).find("too narrow"), std::string::npos);
  EXPECT_NE(fixed_range_problem(-1e308, 1e308).find("within +-1e+12"), std::string::npos);
  EXPECT_NE(fixed_range_problem(1, 1).find("max must exceed min"), std::string::npos);
  EXPECT_NE(fixed_range_problem(2, 1).find("max must exceed min"), std::string::npos);
  EXPECT_NE(fixed_range_problem(NAN, 1).find("finite"), std::string::npos);
  EXPECT_NE(fixed_range_problem(0, 1e-13).find("too narrow"), std::string::npos);
}
