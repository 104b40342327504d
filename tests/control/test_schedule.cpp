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
  CaScheduler s(
      schedule_of(
          R"([{"ca": 0.5, "hold": "steady"}, {"steps": {"to": 1.2, "by": 0.25, "hold": "steady"}}])"),
      st);
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

namespace {
// Feeds flat samples (steady at once with a loose tolerance) every dt until t_end; returns the
// steady events' (t, Ca) in order.
std::vector<std::pair<double, double>> run_flat(CaScheduler& s, double t0, double t_end,
                                                double dt = 0.01) {
  std::vector<std::pair<double, double>> out;
  for (double t = t0 + dt; t <= t_end + 1e-9; t += dt) {
    const auto ev = s.sample(t, 1, 1, 1);
    if (ev.steady) out.emplace_back(t, ev.steady_ca);
  }
  return out;
}
SteadyOptions quick() {
  SteadyOptions st;
  st.window = 0.1;
  st.min_hold = 0.5;
  return st;
}
}  // namespace

// The regression of Milestone 7: steady.csv and the "steady" events carried the next level's Ca.
TEST(Schedule, SteadyEventsCarryTheCaThatWasHeld) {
  CaScheduler s(
      schedule_of(
          R"([{"ca": 0.1, "hold": "steady"}, {"steps": {"to": 0.4, "by": 0.1, "hold": "steady"}}])"),
      quick());
  const auto steady = run_flat(s, 0, 10);
  ASSERT_EQ(steady.size(), 4u);
  const double expect[] = {0.1, 0.2, 0.3, 0.4};
  for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(steady[k].second, expect[k], 1e-12) << k;
  EXPECT_TRUE(s.in_final_hold());
}

// Editing the running ramp's rate continues from the current Ca: no jump back to the first hold.
TEST(Schedule, EditingTheRunningRampContinuesWithoutAJump) {
  const char* before = R"([{"ca": 0.45, "hold": 1.0}, {"ramp": {"to": 1.0, "rate": 0.05}}])";
  const char* after = R"([{"ca": 0.45, "hold": 1.0}, {"ramp": {"to": 1.0, "rate": 0.2}}])";
  CaScheduler s(schedule_of(before), quick());
  run_flat(s, 0, 3.5);  // the ramp began at t = 1: Ca(3.5) = 0.45 + 0.05 * 2.5
  const double ca = s.ca(3.5);
  EXPECT_NEAR(ca, 0.575, 1e-12);
  s.edit(schedule_of(after), 3.5);
  EXPECT_NEAR(s.ca(3.5), ca, 1e-15);        // no jump
  EXPECT_NEAR(s.ca(4.5), ca + 0.2, 1e-12);  // the new rate from the current Ca
  EXPECT_EQ(s.segment_index(), 1);          // the hold is not replayed
  EXPECT_NEAR(s.ca(100), 1.0, 1e-12);
}

TEST(Schedule, EditingStepsKeepsTheLevelHeldAndItsTime) {
  CaScheduler s(
      schedule_of(R"([{"ca": 0.1, "hold": 1.0}, {"steps": {"to": 0.5, "by": 0.1, "hold": 1.0}}])"),
      quick());
  run_flat(s, 0, 2.5);  // at t = 2.5: level 0.3 (held since t = 2)
  EXPECT_NEAR(s.ca(2.5), 0.3, 1e-12);
  s.edit(
      schedule_of(R"([{"ca": 0.1, "hold": 1.0}, {"steps": {"to": 0.9, "by": 0.3, "hold": 1.0}}])"),
      2.5);
  EXPECT_NEAR(s.ca(2.5), 0.3, 1e-12);
  run_flat(s, 2.5, 3.05);  // the level's hold ends at t = 3 as before: then by the new increment
  EXPECT_NEAR(s.ca(3.05), 0.6, 1e-12);
}

TEST(Schedule, ChangingAHoldTimeKeepsTheTimeHeld) {
  CaScheduler s(schedule_of(R"([{"ca": 0.2, "hold": 5.0}, {"ca": 0.4, "hold": 1.0}])"), quick());
  run_flat(s, 0, 2.0);
  s.edit(schedule_of(R"([{"ca": 0.2, "hold": 3.0}, {"ca": 0.4, "hold": 1.0}])"), 2.0);
  run_flat(s, 2.0, 3.05);
  EXPECT_NEAR(s.ca(3.05), 0.4, 1e-12);  // held 3 in all, not 3 more
}

// "Step up from where you are": a schedule that begins with steps (or a ramp) starts from the
// current Ca, in a live edit and after start.from.
TEST(Schedule, ASchedulesFirstStepsOrRampStartFromTheCurrentCa) {
  CaScheduler s(schedule_of("0.3"), quick());
  run_flat(s, 0, 2.0);  // steady at 0.3: in the final hold
  s.edit(schedule_of(R"([{"steps": {"to": 0.5, "by": 0.1, "hold": "steady"}}])"), 2.0);
  EXPECT_NEAR(s.ca(2.0), 0.4, 1e-12);
  CaScheduler r(schedule_of(R"([{"ramp": {"to": 1.0, "rate": 0.1}}])"), quick(), 5.0, 0.6);
  EXPECT_NEAR(r.ca(5.0), 0.6, 1e-12);
  EXPECT_NEAR(r.ca(6.0), 0.7, 1e-12);
  // From rest there is no current Ca: steps start at 0, a ramp is refused.
  CaScheduler q(schedule_of(R"([{"steps": {"to": 0.3, "by": 0.1}}])"), quick());
  EXPECT_NEAR(q.ca(0), 0.1, 1e-12);
  EXPECT_THROW(CaScheduler(schedule_of(R"([{"ramp": {"to": 1.0, "rate": 0.1}}])"), quick()),
               std::invalid_argument);
}

TEST(Schedule, CompletedSegmentsAreNotReplayedAndANewPlanStartsHere) {
  CaScheduler s(schedule_of(R"([{"ca": 0.3, "hold": 1.0}, {"ca": 0.5, "hold": 1.0}])"), quick());
  run_flat(s, 0, 1.5);
  // appending after the running segment: nothing changes now
  s.edit(
      schedule_of(
          R"([{"ca": 0.3, "hold": 1.0}, {"ca": 0.5, "hold": 1.0}, {"ramp": {"to": 0.9, "rate": 1}}])"),
      1.5);
  EXPECT_NEAR(s.ca(1.5), 0.5, 1e-12);
  run_flat(s, 1.5, 2.2);
  EXPECT_NEAR(s.ca(2.2), 0.5 + 1.0 * (2.2 - 2.0), 1e-9);  // the ramp from 0.5
  // a list whose completed part differs is a new plan, from the current Ca
  const double now = s.ca(2.2);
  s.edit(schedule_of(R"([{"ramp": {"to": 0.1, "rate": 1}}])"), 2.2);
  EXPECT_NEAR(s.ca(2.2), now, 1e-12);
  EXPECT_NEAR(s.ca(2.3), now - 0.1, 1e-12);
}

TEST(Schedule, ConstantCaEditJumpsToTheNewLevel) {
  CaScheduler s(schedule_of("0.3"), quick());
  s.sample(0.2, 1, 1, 1);
  s.edit(schedule_of("0.5"), 0.2);
  EXPECT_DOUBLE_EQ(s.ca(0.2), 0.5);
  const auto steady = run_flat(s, 0.2, 2.0);
  ASSERT_EQ(steady.size(), 1u);
  EXPECT_DOUBLE_EQ(steady[0].second, 0.5);
}

TEST(Schedule, AContinuationIsRefusedByTheRunsScheduler) {
  const ControlOptions o =
      parse_control(R"({"ca": {"continuation": {"from": 0.15, "to": 1, "step": 0.05}}})").options;
  try {
    CaScheduler s(o.ca, o.steady);
    FAIL() << "a continuation was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("capflow steady"), std::string::npos) << e.what();
  }
}
