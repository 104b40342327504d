// Checkpoint/restart: N steps + resume + N steps equals 2N steps bit for bit; bad checkpoints
// are refused with a clear message.
#include <gtest/gtest.h>

#include <cstring>

#include "app/simulation.h"
#include "control/control_file.h"
#include "output/checkpoint.h"
#include "test_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {
control::ControlOptions options(const fs::path& dir, double t_end) {
  control::ParsedControl p = control::parse_control(R"({
    "capsule": {"law": "neo-hookean"}, "mesh": {"elements": 6, "nb": 6},
    "time": {"dt": 0.004, "t_end": 0.04},
    "ca": [{"ca": 0.2, "hold": 0.02}, {"ramp": {"to": 0.4, "rate": 2.0}}],
    "steady": {"window": 0.01, "min_hold": 0.0, "tolerance": 1e-9},
    "output": {"csv_every": 0.008}})");
  p.options.output.dir = dir.string();
  p.options.time.t_end = t_end;
  return p.options;
}
std::vector<double> final_x(const fs::path& dir) {
  return output::Checkpoint::read(app::Simulation::latest_checkpoint(dir.string())).doubles("x");
}
}  // namespace

TEST(Restart, ResumedRunIsBitIdenticalToAnUninterruptedOne) {
  const fs::path a = test::fresh_dir("full"), b = test::fresh_dir("split");
  {
    app::Simulation sim(options(a, 0.08), "");
    const app::RunSummary s = sim.run();
    ASSERT_EQ(s.steps, 20);
  }
  {
    app::Simulation sim(options(b, 0.04), "");
    ASSERT_EQ(sim.run().steps, 10);
  }
  {
    app::ResumeOverrides ov;
    ov.t_end = 0.08;
    auto sim = app::Simulation::resume(b.string(), ov);
    const app::RunSummary s = sim->run();
    ASSERT_EQ(s.steps, 20);
  }
  const std::vector<double> xa = final_x(a), xb = final_x(b);
  ASSERT_EQ(xa.size(), xb.size());
  EXPECT_EQ(std::memcmp(xa.data(), xb.data(), xa.size() * sizeof(double)), 0);
  // The time series of the split run has the same rows as the uninterrupted one (wall time aside).
  auto strip = [](std::vector<std::string> v) {
    for (auto& l : v) l = l.substr(0, l.rfind(','));
    return v;
  };
  EXPECT_EQ(strip(test::lines_of(a / "timeseries.csv")), strip(test::lines_of(b / "timeseries.csv")));
  // The ramp started at t = 0.02 and Ca was continuous across the restart.
  EXPECT_NE(test::read_file(b / "events.jsonl").find("\"event\":\"resume\""), std::string::npos);
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(Restart, RefusesMissingAndCorruptCheckpoints) {
  const fs::path d = test::fresh_dir("bad");
  try {
    app::Simulation::resume(d.string(), {});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no checkpoint"), std::string::npos);
  }
  fs::create_directories(d / "checkpoints");
  test::write_file(d / "checkpoints" / "ckpt_0000000001.ckpt", "garbage");
  try {
    app::Simulation::resume(d.string(), {});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not a capflow checkpoint"), std::string::npos);
  }
  fs::remove_all(d);
}

TEST(SteadyStop, RunEndsAtTheSteadyStateOfTheFinalLevel) {
  // A loose tolerance makes the first admissible sample steady; with steady.stop the run ends
  // there (the last row and the steady row are written), without it the run goes on to t_end.
  auto opts = [](const fs::path& dir, bool stop) {
    control::ParsedControl p = control::parse_control(R"({
      "capsule": {"law": "neo-hookean"}, "mesh": {"elements": 6, "nb": 6},
      "time": {"dt": 0.004, "t_end": 0.2}, "ca": 0.2,
      "steady": {"window": 0.02, "min_hold": 0.04, "tolerance": 1.0},
      "output": {"csv_every": 0.02}})");
    p.options.output.dir = dir.string();
    p.options.steady.stop = stop;
    return p.options;
  };
  const fs::path a = test::fresh_dir("stop"), b = test::fresh_dir("nostop");
  app::Simulation sa(opts(a, true), "");
  const app::RunSummary ra = sa.run();
  app::Simulation sb(opts(b, false), "");
  const app::RunSummary rb = sb.run();
  EXPECT_NE(ra.reason.find("steady.stop"), std::string::npos) << ra.reason;
  EXPECT_EQ(ra.steady_states, 1);
  EXPECT_LT(ra.t, 0.1);
  EXPECT_GT(ra.t, 0.039);
  EXPECT_NEAR(rb.t, 0.2, 1e-9);
  EXPECT_EQ(test::lines_of(a / "steady.csv").size(), 2u);  // header + one row
}
