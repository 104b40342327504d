// Ca schedule engine: levels, ramps, steps and steady-state detection on synthetic signals.
#include <gtest/gtest.h>

#include <cmath>

#include "control/control_file.h"
#include "control/schedule.h"

using namespace capflow::control;

namespace {
CaSchedule schedule_of(const char* ca_json) {
  return parse_control(std::string("{\"ca\": ") + ca_json + "}").options.ca;
}
// A shape relaxing exponentially to a level-dependent steady state: L = 1 + Ca (1 - e^{-(t-t0)}).
struct Relaxing {
  double t0 = 0, from = 1, to = 1;
  double L(double t) const { return to + (from - to) * std::exp(-(t - t0)); }
};
}  // namespace

TEST(Schedule, ConstantCaReportsOneSteadyState) {
  SteadyOptions st;
  st.tolerance = 1e-3;
  st.window = 0.5;
  st.min_hold = 1.0;
  CaScheduler s(schedule_of("0.45"), st);
  Relaxing r{0, 1, 1.45};
  int steady = 0;
  double t_steady = -1;
  for (int k = 1; k <= 2000; ++k) {
    const double t = k * 0.01;
    const auto ev = s.sample(t, r.L(t), 2 - r.L(t), 1.0);
    EXPECT_DOUBLE_EQ(s.ca(t), 0.45);
    if (ev.steady) {
      ++steady;
      if (t_steady < 0) t_steady = t;
    }
  }
  EXPECT_EQ(steady, 1);
  // |dL/dt| = 0.45 e^{-t} (averaged over the window) < 1e-3 first near t ~ 6.3.
  EXPECT_GT(t_steady, 5.5);
  EXPECT_LT(t_steady, 7.5);
}

TEST(Schedule, HoldForATimeThenRamp) {
  CaScheduler s(schedule_of(R"([{"ca": 0.5, "hold": 2.0}, {"ramp": {"to": 1.0, "rate": 0.25}}])"),
                SteadyOptions{});
  double t = 0;
  for (; t < 2.0 - 1e-9; t += 0.01) {
    s.sample(t + 0.01, 1, 1, 1);
  }
  // The ramp starts at t = 2 from 0.5 and reaches 1.0 at t = 4.
  EXPECT_NEAR(s.ca(3.0), 0.75, 1e-12);
  EXPECT_NEAR(s.ca(3.9), 0.975, 1e-12);
  EXPECT_NEAR(s.ca(5.0), 1.0, 1e-12);  // clipped
  for (; t < 4.05; t += 0.01) s.sample(t + 0.01, 1, 1, 1);
  EXPECT_TRUE(s.in_final_hold());
  EXPECT_DOUBLE_EQ(s.ca(10.0), 1.0);
}

TEST(Schedule, StepsWaitForSteadyStateAtEachLevel) {
  SteadyOptions st;
  st.tolerance = 1e-3;
  st.window = 0.5;
  st.min_hold = 1.0;
  CaScheduler s(schedule_of(R"([{"ca": 0.5, "hold": "steady"}, {"steps": {"to": 1.2, "by": 0.25, "hold": "steady"}}])"), st);
  Relaxing r{0, 1, 1.5};
  std::vector<double> levels;
  double last_ca = s.ca(0);
  levels.push_back(last_ca);
  int steady = 0;
  for (int k = 1; k <= 10000 && !s.in_final_hold(); ++k) {
    const double t = k * 0.01;
    const auto ev = s.sample(t, r.L(t), 1, 1);
    steady += ev.steady;
    if (s.ca(t) != last_ca) {
      last_ca = s.ca(t);
      levels.push_back(last_ca);
      r = Relaxing{t, r.L(t), 1 + last_ca};
    }
  }
  ASSERT_EQ(levels.size(), 4u);  // 0.5, 0.75, 1.0, 1.2 (last increment clipped)
  EXPECT_DOUBLE_EQ(levels[1], 0.75);
  EXPECT_DOUBLE_EQ(levels[2], 1.0);
  EXPECT_DOUBLE_EQ(levels[3], 1.2);
  EXPECT_EQ(steady, 4);  // one per level, the last one ends the schedule
}

TEST(Schedule, ReplaceContinuesFromTheCurrentCa) {
  CaScheduler s(schedule_of("0.3"), SteadyOptions{});
  s.sample(1.0, 1, 1, 1);
  s.replace(schedule_of(R"([{"ca": 0.3}, {"ramp": {"to": 0.5, "rate": 0.1}}])"), SteadyOptions{}, 1.0);
  // First segment is a hold at 0.3 until steady; give it a flat signal so it becomes steady.
  double t = 1.0;
  while (!s.in_final_hold() && t < 20) {
    t += 0.01;
    s.sample(t, 1, 1, 1);
  }
  EXPECT_TRUE(s.in_final_hold());
  EXPECT_DOUBLE_EQ(s.ca(t + 1), 0.5);
}
