// Milestone 17 (the second hostile round): numbers bounded where they enter the control file, a
// sweep, a schedule and a live edit - no allocation sized by user input, no overflow, no value
// that reaches the renderer or libgomp unchecked.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "control/control_file.h"
#include "control/edit.h"
#include "control/schedule.h"
#include "control/sweep.h"

using namespace capflow::control;

namespace {

std::string issues_of(const std::string& text) {
  try {
    parse_control(text, "t.json");
  } catch (const ControlError& e) {
    std::string all;
    for (const auto& i : e.issues()) all += i.str() + "\n";
    return all;
  }
  return "";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(ControlBounds, RenderRangeMustBeResolvable) {
  // [-1e308, 1e308] hung a run at its first frame; [1e16, 1e16 + 2] killed its renderer
  EXPECT_TRUE(has(issues_of(R"({"ca": 0.4, "render": {"range": [-1e308, 1e308]}})"),
                  "render.range: value [-1e+308,1e+308] is not valid"));
  EXPECT_TRUE(has(issues_of(R"({"ca": 0.4, "render": {"range": [1e16, 10000000000000002]}})"),
                  "render.range"));
  EXPECT_TRUE(has(issues_of(R"({"ca": 0.4, "render": {"range": [0.5, 0.5000000000001]}})"),
                  "too narrow"));
  EXPECT_EQ(issues_of(R"({"ca": 0.4, "render": {"range": [-2, 3.5]}})"), "");
}

TEST(ControlBounds, StepsSegmentsHoldABoundedNumberOfLevels) {
  // {"to": 100, "by": 1e-9} made capflow steady allocate 1e11 levels (std::bad_alloc, exit 3)
  EXPECT_TRUE(has(issues_of(R"({"ca": [{"steps": {"to": 100, "by": 1e-9}}]})"),
                  "ca[0].steps.by: value 1e-09 makes 1e+11 levels from Ca = 0 to 100"));
  EXPECT_TRUE(has(issues_of(R"({"ca": [{"ca": 0.5}, {"steps": {"to": 0.6, "by": 1e-7}}]})"),
                  "ca[1].steps.by"));
  EXPECT_EQ(issues_of(R"({"ca": [{"ca": 0.5}, {"steps": {"to": 0.6, "by": 1e-6}}]})"), "");
  // after start.from the first segment starts at the source's Ca: checked when it is known
  EXPECT_EQ(issues_of(R"({"ca": [{"steps": {"to": 100, "by": 1e-9}}], "start": {"from": "r"}})"),
            "");
  const CaSchedule s = parse_control(R"({"ca": [{"steps": {"to": 100, "by": 1e-9}}],
                                         "start": {"from": "r"}})")
                           .options.ca;
  EXPECT_THROW(CaScheduler(s, SteadyOptions{}, 0.0, 99.99), std::invalid_argument);
  EXPECT_NO_THROW(CaScheduler(s, SteadyOptions{}, 0.0, 100 - 1e-5));
  EXPECT_THROW(schedule_levels(s, 0.0), std::invalid_argument);
  EXPECT_EQ(schedule_levels(s, 100 - 2e-9).size(), 2u);
  EXPECT_EQ(steps_levels(s.segments[0], 0.0), 1e11);
}

TEST(ControlBounds, StartFromMustNameSomething) {
  EXPECT_TRUE(has(issues_of(R"({"ca": 0.4, "start": {"from": ""}})"),
                  "start.from: expected a non-empty string"));
}

TEST(ControlBounds, SweepRangesDoNotOverflow) {
  // -1e308 .. 1e308 made an infinite middle value, a JSON parse error and exit 3
  try {
    parse_sweep(R"({"base": {"ca": 0.3}, "vary": {"ca": {"from": -1e308, "to": 1e308,
                   "count": 3}}})",
                "s.json", ".", "out");
    FAIL();
  } catch (const ControlError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(has(m, "case 1 (ca = 0)")) << m;
    EXPECT_TRUE(has(m, "case 2 (ca = 1e+308)")) << m;
  }
  const SweepPlan p = parse_sweep(
      R"({"base": {"ca": 0.3}, "vary": {"capsule.C": {"from": -0.4, "to": 1e4, "count": 3}}})",
      "s.json", ".", "out");
  EXPECT_EQ(p.cases.size(), 3u);
  EXPECT_EQ(p.cases[2].values[0].second, "10000");
}

TEST(ControlBounds, RunKeysOfARefusedEditAreHonoured) {
  // a stop saved with a value the edit refuses (t_end too far for a fixed dt of 1e-6)
  const std::string doc =
      R"({"ca": 0.3, "time": {"dt": 1e-6, "t_end": 50}, "run": {"state": "stopped"}})";
  EXPECT_TRUE(has(issues_of(doc), "time.t_end"));
  const auto run = run_keys_of(doc);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->state, RunState::Stopped);
  EXPECT_FALSE(run_keys_of(R"({"ca": 0.3, "run": {"state": "halted"}})"));
  EXPECT_FALSE(run_keys_of("not json"));
  EXPECT_FALSE(run_keys_of(R"({"ca": 0.3})"));
}

TEST(ControlBounds, AFrozenRestoreVolumeEditIsRefusedNotDropped) {
  const ControlOptions before = parse_control(R"({"ca": 0.3})").options;
  const ControlOptions after =
      parse_control(R"({"ca": 0.3, "start": {"restore_volume": false}})").options;
  const EditResult r = apply_edit(before, before, after);
  ASSERT_EQ(r.refused.size(), 1u);
  EXPECT_EQ(r.refused[0].path, "start.restore_volume");
  EXPECT_TRUE(r.applied.empty());
}

// Milestone 16: the edit policy as data - each command's live keys come from the schema, and
// every changed key gets a typed outcome with its message.
TEST(EditPolicy, EachCommandTakesItsLiveKeysFromTheSchema) {
  const ControlOptions before = parse_control(R"({"ca": 0.3})").options;
  const ControlOptions after = parse_control(R"({"ca": 0.4, "output": {"csv_every": 0.5},
      "mesh": {"nb": 8}, "time": {"tolerance": 1e-7}})").options;
  EditPolicy run;
  run.command = Command::Run;
  const EditResult r = apply_edit(before, before, after, run);
  ASSERT_EQ(r.applied.size(), 3u);  // ca, time.tolerance, output.csv_every
  ASSERT_EQ(r.refused.size(), 1u);
  EXPECT_EQ(r.refused[0].path, "mesh.nb");
  EXPECT_EQ(r.refused[0].outcome, EditOutcome::Frozen);
  EditPolicy steady;
  steady.command = Command::Steady;
  const EditResult s = apply_edit(before, before, after, steady);
  ASSERT_EQ(s.applied.size(), 2u);
  std::set<std::string> live;
  for (const OptionChange& c : s.applied) live.insert(c.path);
  EXPECT_EQ(live, (std::set<std::string>{"ca", "time.tolerance"}));
  ASSERT_EQ(s.refused.size(), 2u);
  for (const OptionChange& c : s.refused) {
    if (c.path == "output.csv_every") {
      EXPECT_EQ(c.outcome, EditOutcome::NotForCommand);
      EXPECT_TRUE(has(c.reason, "capflow steady does not use it"));
    } else {
      EXPECT_EQ(c.path, "mesh.nb");
      EXPECT_EQ(c.outcome, EditOutcome::Frozen);
    }
  }
  // the schema says so, for every key
  for (const FieldInfo& f : control_fields()) {
    if (f.mutability == Mutability::Live) {
      EXPECT_TRUE(f.live_for(Command::Run)) << f.path;
    }
  }
  EXPECT_EQ(s.merged.output.csv_every, before.output.csv_every);
  EXPECT_EQ(s.merged.time.tolerance, 1e-7);
}

TEST(EditPolicy, AVetoRefusesAChangeAsInvalidAndTheRestApplies) {
  const ControlOptions before = parse_control(R"({"ca": 0.3})").options;
  const ControlOptions after =
      parse_control(R"({"ca": {"continuation": {"from": 0.1, "to": 1, "step": 0.1}},
                        "time": {"t_end": 5}})")
          .options;
  EditPolicy p;
  p.veto = [](const OptionChange& c, const ControlOptions& merged) {
    return c.path == "ca" && merged.ca.continuation ? std::string("a continuation is steady's")
                                                    : std::string();
  };
  const EditResult r = apply_edit(before, before, after, p);
  ASSERT_EQ(r.refused.size(), 1u);
  EXPECT_EQ(r.refused[0].outcome, EditOutcome::Invalid);
  EXPECT_EQ(r.refused[0].reason, "a continuation is steady's");
  EXPECT_FALSE(r.schedule_changed);
  ASSERT_EQ(r.applied.size(), 1u);
  EXPECT_EQ(r.applied[0].path, "time.t_end");
  EXPECT_FALSE(r.merged.ca.continuation);
  // the events.jsonl record names the outcome
  EXPECT_TRUE(has(change_record(r.refused[0]).text(), "\"refused\":\"invalid\""));
}
