// Adaptive time steps in a run (time.dt "auto"): output times and schedule changes are hit
// exactly, a resumed run continues bit for bit, and live edits switch between auto and fixed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "app/simulation.h"
#include "control/control_file.h"
#include "output/checkpoint.h"
#include "output/records.h"
#include "process_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {

control::ControlOptions auto_options(const fs::path& dir, double t_end,
                                     control::TimeMethod method = control::TimeMethod::CashKarp) {
  control::ParsedControl p = control::parse_control(R"({
    "capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 6, "division": "cube"},
    "time": {"dt": "auto"},
    "ca": [{"ca": 0.2, "hold": 0.13}, {"ramp": {"to": 0.3, "rate": 1.0}}],
    "steady": {"window": 1.0, "min_hold": 0.0, "tolerance": 1e-9},
    "output": {"csv_every": 0.05, "checkpoint_every": 0.1}})");
  p.options.output.dir = dir.string();
  p.options.time.t_end = t_end;
  p.options.time.method = method;
  return p.options;
}

// A run split at t = 0.2 and resumed from its checkpoint ends as the uninterrupted one does, bit
// for bit: the integrator's next step and controller memory travel in the checkpoint.
void expect_resume_bit_identical(control::TimeMethod method, const std::string& name) {
  const fs::path a = test::fresh_dir(name + "_full"), b = test::fresh_dir(name + "_split");
  long steps = 0;
  {
    app::Simulation sim(auto_options(a, 0.3, method), "");
    const app::RunSummary s = sim.run();
    ASSERT_FALSE(s.failed) << s.failure;
    steps = s.steps;
  }
  {
    app::Simulation sim(auto_options(b, 0.2, method), "");
    ASSERT_FALSE(sim.run().failed);
  }
  {
    app::ResumeOverrides ov;
    ov.t_end = 0.3;
    auto sim = app::Simulation::resume(b.string(), ov);
    EXPECT_EQ(sim->run().steps, steps);
  }
  const auto x = [](const fs::path& dir) {
    return output::Checkpoint::read(app::Simulation::latest_checkpoint(dir.string())).doubles("x");
  };
  const std::vector<double> xa = x(a), xb = x(b);
  ASSERT_EQ(xa.size(), xb.size());
  EXPECT_EQ(std::memcmp(xa.data(), xb.data(), xa.size() * sizeof(double)), 0);
  auto strip = [](std::vector<std::string> v) {
    for (auto& l : v) l = l.substr(0, l.rfind(','));
    return v;
  };
  EXPECT_EQ(strip(test::lines_of(a / "timeseries.csv")),
            strip(test::lines_of(b / "timeseries.csv")));
  fs::remove_all(a);
  fs::remove_all(b);
}

}  // namespace

TEST(TimeSteps, OutputTimesAndScheduleChangesAreHitExactly) {
  const fs::path d = test::fresh_dir("auto_breakpoints");
  app::Simulation sim(auto_options(d, 0.4), "");
  const app::RunSummary s = sim.run();
  ASSERT_FALSE(s.failed) << s.failure;
  EXPECT_EQ(s.t, 0.4);
  const std::vector<double> t = test::csv_column(d / "timeseries.csv", "t");
  const std::vector<double> dt = test::csv_column(d / "timeseries.csv", "dt");
  ASSERT_EQ(t.size(), 9u);  // 0, 0.05, ..., 0.4
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], 0.05 * i, 1e-14) << "row " << i;
  // The steps vary (the first ones are short: the capsule starts to move at rate 1/Ca).
  EXPECT_LT(*std::min_element(dt.begin() + 1, dt.end()), *std::max_element(dt.begin(), dt.end()));
  // The hold ended at t = 0.13 exactly and the ramp at 0.23 (a step ended there).
  const std::string events = test::read_file(d / "events.jsonl");
  EXPECT_NE(events.find("held for 0.13 (t = 0.13)"), std::string::npos) << events;
  EXPECT_NE(events.find("ramp reached Ca = 0.3 (t = 0.23)"), std::string::npos) << events;
  fs::remove_all(d);
}

TEST(TimeSteps, ResumedAutoStepRunIsBitIdentical) {
  expect_resume_bit_identical(control::TimeMethod::CashKarp, "auto");
}

TEST(TimeSteps, ResumedChebyshevRunIsBitIdentical) {
  expect_resume_bit_identical(control::TimeMethod::Chebyshev, "chebyshev");
}

TEST(TimeSteps, FixedStepsAreTheRk4StepsOfBefore) {
  // time.dt as a number: RK4 with that step, ending at the step that reaches t_end - dt/2.
  const fs::path d = test::fresh_dir("fixed_steps");
  control::ControlOptions o = auto_options(d, 0.1);
  o.time.adaptive = false;
  o.time.dt = 0.004;
  app::Simulation sim(o, "");
  const app::RunSummary s = sim.run();
  EXPECT_EQ(s.steps, 25);
  for (double v : test::csv_column(d / "timeseries.csv", "dt"))
    if (v != 0) {
      EXPECT_EQ(v, 0.004);
    }
  fs::remove_all(d);
}

TEST(TimeSteps, LiveEditsSwitchBetweenAutoAndFixedSteps) {
  const fs::path d = test::fresh_dir("auto_live");
  const fs::path ctl = d / "control.json", run = d / "run";
  const auto control = [](const std::string& time) {
    return R"({"mesh": {"elements": 6, "nb": 6}, "time": )" + time +
           R"(, "output": {"csv_every": 0.01}, "numerics": {"threads": 1}, "ca": 0.3})";
  };
  test::write_file(ctl, control(R"({"dt": "auto", "t_end": 1000})"));
  const pid_t pid =
      test::spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= 5; }, 60));
  test::write_file(ctl, control(R"({"dt": 0.0025, "t_end": 1000})"));
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "edit") >= 1; }, 20));
  const long rows1 = test::csv_rows(run / "timeseries.csv");
  ASSERT_TRUE(
      test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") > rows1 + 3; }, 30));
  test::write_file(ctl, control(R"({"dt": "auto", "tolerance": 1e-8, "t_end": 1000})"));
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "edit") >= 2; }, 20));
  const long rows2 = test::csv_rows(run / "timeseries.csv");
  ASSERT_TRUE(
      test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") > rows2 + 3; }, 30));
  test::write_file(ctl, control(R"({"dt": "auto", "tolerance": 1e-8, "t_end": 1000},
                                   "run": {"state": "stopped"})"));
  EXPECT_EQ(test::wait_exit(pid, 30), 0) << test::read_file(d / "stderr.log");

  std::vector<double> t_edit;
  for (const auto& e : test::events(run))
    if (e["event"] == "edit") {
      EXPECT_TRUE(e["accepted"].get<bool>()) << e.dump();
      t_edit.push_back(e["t"]);
    }
  ASSERT_GE(t_edit.size(), 2u);
  const std::vector<double> t = test::csv_column(run / "timeseries.csv", "t");
  const std::vector<double> dt = test::csv_column(run / "timeseries.csv", "dt");
  int fixed = 0, adaptive_after = 0, kept_after = 0;
  for (size_t i = 1; i < t.size(); ++i) {
    if (t[i] > t_edit[0] + 1e-12 && t[i] <= t_edit[1] + 1e-12) {
      EXPECT_EQ(dt[i], 0.0025) << "t = " << t[i];  // fixed steps from the step after the edit
      ++fixed;
    }
    // Back on auto: the integrator starts from the last step (0.0025), then adapts; a row may
    // fall on that first step.
    if (t[i] > t_edit[1] + 1e-12) ++(dt[i] == 0.0025 ? kept_after : adaptive_after);
  }
  EXPECT_GT(fixed, 2);
  EXPECT_GT(adaptive_after, 2);
  EXPECT_LE(kept_after, 1);
  const std::string log = test::read_file(d / "stderr.log");
  EXPECT_NE(log.find("time.dt \"auto\" -> 0.0025"), std::string::npos) << log;
  fs::remove_all(d);
}

TEST(TimeSteps, AResumedRunFromBeforeTheDtColumnGetsIt) {
  // A run directory written before timeseries.csv had its dt column (simulated by removing it):
  // the resume inserts the column, empty, so that every row lines up with the header.
  const fs::path d = test::fresh_dir("old_timeseries");
  control::ControlOptions o = auto_options(d, 0.1);
  o.time.adaptive = false;
  o.time.dt = 0.004;
  {
    app::Simulation sim(o, "");
    ASSERT_FALSE(sim.run().failed);
  }
  std::string old;
  for (std::string line : test::lines_of(d / "timeseries.csv")) {
    const size_t last = line.rfind(','), before = line.rfind(',', last - 1);
    old += line.substr(0, before) + line.substr(last) + "\n";
  }
  test::write_file(d / "timeseries.csv", old);
  ASSERT_EQ(old.find(",dt,"), std::string::npos);
  {
    app::ResumeOverrides ov;
    ov.t_end = 0.2;
    auto sim = app::Simulation::resume(d.string(), ov);
    ASSERT_FALSE(sim->run().failed);
  }
  const std::vector<std::string> lines = test::lines_of(d / "timeseries.csv");
  EXPECT_NE(lines.at(0).find(",steps,dt,wall_s"), std::string::npos) << lines[0];
  for (const std::string& l : lines) EXPECT_EQ(std::count(l.begin(), l.end(), ','), 19) << l;
  const std::string& last = lines.back();  // a row of the resumed session: dt filled in
  const size_t end = last.rfind(','), begin = last.rfind(',', end - 1);
  EXPECT_EQ(std::stod(last.substr(begin + 1, end - begin - 1)), 0.004) << last;
  fs::remove_all(d);
}

namespace {

// A CSV line's fields (a trailing comma ends with an empty one).
std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> f;
  std::istringstream in(line);
  for (std::string x; std::getline(in, x, ',');) f.push_back(x);
  if (!line.empty() && line.back() == ',') f.emplace_back();
  return f;
}

// The lines of a CSV file without the named columns.
std::string without_columns(const fs::path& file, const std::vector<std::string>& names) {
  std::vector<bool> keep;
  std::string out;
  for (const std::string& line : test::lines_of(file)) {
    const std::vector<std::string> f = fields_of(line);
    if (keep.empty())
      for (const std::string& x : f)
        keep.push_back(std::find(names.begin(), names.end(), x) == names.end());
    std::string row;
    for (size_t i = 0; i < f.size(); ++i)
      if (keep.at(i)) row += (row.empty() ? "" : ",") + f[i];
    out += row + "\n";
  }
  return out;
}

}  // namespace

TEST(TimeSteps, RowsCarryTheBendingEnergyAndAResumeFromBeforeThatColumnGetsIt) {
  // A sphere with Helfrich bending (c0 = 0) at rest: W_b = (kappa_b / 2) INT (2 H)^2 dA =
  // 8 pi Eb on the unit sphere, in the row at t = 0. The same run directory with its
  // bending_energy and dt columns removed (a run of an earlier capflow) resumes: the header
  // becomes today's, the old rows get the columns empty, the new ones filled.
  const fs::path d = test::fresh_dir("bending_column");
  control::ParsedControl p = control::parse_control(R"({
    "capsule": {"law": "skalak", "C": 1, "bending": {"modulus": 0.01}},
    "mesh": {"elements": 6, "nb": 8, "division": "cube"}, "ca": 0.1,
    "time": {"dt": 0.004, "t_end": 0.1},
    "output": {"csv_every": 0.05, "checkpoint_every": 0.1}})");
  p.options.output.dir = d.string();
  {
    app::Simulation sim(p.options, "");
    ASSERT_FALSE(sim.run().failed);
  }
  const auto column = [&](const std::vector<std::string>& lines, size_t row) {
    const std::vector<std::string> head = fields_of(lines.at(0)), f = fields_of(lines.at(row));
    const size_t i = std::find(head.begin(), head.end(), "bending_energy") - head.begin();
    return i < f.size() ? f[i] : std::string("missing");
  };
  std::vector<std::string> lines = test::lines_of(d / "timeseries.csv");
  ASSERT_EQ(lines.size(), 4u);  // t = 0, 0.05, 0.1
  EXPECT_NEAR(std::stod(column(lines, 1)), 8 * M_PI * 0.01, 1e-4 * 8 * M_PI * 0.01);
  EXPECT_GT(std::stod(column(lines, 3)), 0);
  test::write_file(d / "timeseries.csv",
                   without_columns(d / "timeseries.csv", {"bending_energy", "dt"}));
  {
    app::ResumeOverrides ov;
    ov.t_end = 0.2;
    auto sim = app::Simulation::resume(d.string(), ov);
    ASSERT_FALSE(sim->run().failed);
  }
  lines = test::lines_of(d / "timeseries.csv");
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0] + "\n", output::records::timeseries().header());
  for (size_t r = 1; r <= 3; ++r) EXPECT_EQ(column(lines, r), "") << lines[r];
  for (size_t r = 4; r <= 5; ++r) EXPECT_GT(std::stod(column(lines, r)), 0) << lines[r];
  fs::remove_all(d);
}
