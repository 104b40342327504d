// Checkpoint/restart: N steps + resume + N steps equals 2N steps bit for bit; bad checkpoints
// are refused with a clear message.
#include <gtest/gtest.h>

#include <cstring>

#include "app/errors.h"
#include "app/simulation.h"
#include "control/control_file.h"
#include "output/checkpoint.h"
#include "test_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {
control::ControlOptions options(const fs::path& dir, double t_end, double lambda = 1.0) {
  // the axis-aligned cube, so that start.from below goes from it onto the other divisions
  control::ParsedControl p = control::parse_control(R"({
    "capsule": {"law": "neo-hookean"}, "mesh": {"elements": 6, "nb": 6, "division": "cube"},
    "time": {"dt": 0.004, "t_end": 0.04},
    "ca": [{"ca": 0.2, "hold": 0.02}, {"ramp": {"to": 0.4, "rate": 2.0}}],
    "steady": {"window": 0.01, "min_hold": 0.0, "tolerance": 1e-9},
    "output": {"csv_every": 0.008}})");
  p.options.output.dir = dir.string();
  p.options.time.t_end = t_end;
  p.options.viscosity_ratio = lambda;
  return p.options;
}
std::vector<double> final_x(const fs::path& dir) {
  return output::Checkpoint::read(app::Simulation::latest_checkpoint(dir.string())).doubles("x");
}
}  // namespace

// lambda = 1, and lambda = 5 (the checkpoint keeps the warm start of the double-layer solve).
void expect_resume_bit_identical(double lambda) {
  const fs::path a = test::fresh_dir("full"), b = test::fresh_dir("split");
  {
    app::Simulation sim(options(a, 0.08, lambda), "");
    const app::RunSummary s = sim.run();
    ASSERT_EQ(s.steps, 20);
  }
  {
    app::Simulation sim(options(b, 0.04, lambda), "");
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
  EXPECT_EQ(strip(test::lines_of(a / "timeseries.csv")),
            strip(test::lines_of(b / "timeseries.csv")));
  // The ramp started at t = 0.02 and Ca was continuous across the restart.
  EXPECT_NE(test::read_file(b / "events.jsonl").find("\"event\":\"resume\""), std::string::npos);
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(Restart, ResumedRunIsBitIdenticalToAnUninterruptedOne) {
  expect_resume_bit_identical(1.0);
}

TEST(Restart, ResumedRunWithAViscosityRatioIsBitIdentical) {
  expect_resume_bit_identical(5.0);
}

TEST(Restart, RefusesMissingAndCorruptCheckpoints) {
  const fs::path d = test::fresh_dir("bad");
  try {
    app::Simulation::resume(d.string(), {});
    FAIL();
  } catch (const app::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("not a capflow run directory"), std::string::npos)
        << e.what();
  }
  test::write_file(d / "control.json", "{}");
  test::write_file(d / "events.jsonl", "");
  try {
    app::Simulation::resume(d.string(), {});
    FAIL();
  } catch (const app::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("no checkpoint"), std::string::npos) << e.what();
  }
  fs::create_directories(d / "checkpoints");
  test::write_file(d / "checkpoints" / "ckpt_0000000001.ckpt", "garbage");
  try {
    app::Simulation::resume(d.string(), {});
    FAIL();
  } catch (const app::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("not a capflow checkpoint"), std::string::npos)
        << e.what();
  }
  fs::remove_all(d);
}

// A corrupt newest checkpoint: the resume falls back to the newest one that reads, says so, and
// the files continue consistently from it (the time series equals an uninterrupted run's).
TEST(Restart, CorruptNewestCheckpointFallsBackToTheNewestValidOne) {
  const fs::path a = test::fresh_dir("fallback_full"), b = test::fresh_dir("fallback");
  {
    app::Simulation sim(options(a, 0.08), "");
    ASSERT_EQ(sim.run().steps, 20);
  }
  {
    control::ControlOptions o = options(b, 0.08);
    o.output.checkpoint_every = 0.02;
    app::Simulation sim(o, "");
    ASSERT_EQ(sim.run().steps, 20);
  }
  const std::string newest = app::Simulation::latest_checkpoint(b.string());
  std::string bytes = test::read_file(newest);
  bytes[bytes.size() / 2] ^= 0x5a;
  test::write_file(newest, bytes);
  {
    app::ResumeOverrides ov;
    ov.t_end = 0.08;
    auto sim = app::Simulation::resume(b.string(), ov);
    const app::RunSummary s = sim->run();
    EXPECT_EQ(s.steps, 20);
    EXPECT_FALSE(s.failed);
  }
  const std::string log = test::read_file(b / "run.log");
  EXPECT_NE(log.find("skipped a checkpoint that does not read"), std::string::npos) << log;
  EXPECT_NE(log.find("checksum mismatch"), std::string::npos) << log;
  auto strip = [](std::vector<std::string> v) {
    for (auto& l : v) l = l.substr(0, l.rfind(','));
    return v;
  };
  EXPECT_EQ(strip(test::lines_of(a / "timeseries.csv")),
            strip(test::lines_of(b / "timeseries.csv")));
  const std::vector<double> xa = final_x(a), xb = final_x(b);
  ASSERT_EQ(xa.size(), xb.size());
  EXPECT_EQ(std::memcmp(xa.data(), xb.data(), xa.size() * sizeof(double)), 0);
  fs::remove_all(a);
  fs::remove_all(b);
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

namespace {
// Column `name` of the CSV row `row` (0 = first data row) of a timeseries.
double csv_value(const fs::path& csv, size_t row, const std::string& name) {
  const std::vector<std::string> lines = test::lines_of(csv);
  auto split = [](const std::string& l) {
    std::vector<std::string> f;
    std::stringstream ss(l);
    for (std::string c; std::getline(ss, c, ',');) f.push_back(c);
    return f;
  };
  const std::vector<std::string> head = split(lines.at(0)), cells = split(lines.at(row + 1));
  for (size_t k = 0; k < head.size(); ++k)
    if (head[k] == name) return std::stod(cells.at(k));
  ADD_FAILURE() << "no column " << name;
  return NAN;
}
}  // namespace

TEST(StartFrom, RunGoesOnFromAnotherRunsShapeOnAnotherMesh) {
  // Run a deforms the sphere (NE=6 NB=6); run b starts from a's newest checkpoint on NE=10 NB=8.
  const fs::path a = test::fresh_dir("start_src"), b = test::fresh_dir("start_dst");
  {
    app::Simulation sim(options(a, 0.04), "");
    ASSERT_EQ(sim.run().steps, 10);
  }
  const size_t last_a = test::lines_of(a / "timeseries.csv").size() - 2;
  ASSERT_NEAR(csv_value(a / "timeseries.csv", last_a, "t"), 0.04, 1e-12);
  control::ControlOptions ob = options(b, 0.06);
  ob.mesh = {10, 8};
  ob.start.from = a.string();
  {
    app::Simulation sim(ob, "");
    const app::RunSummary s = sim.run();
    EXPECT_EQ(s.steps, 5);  // from t = 0.04 to 0.06
    EXPECT_FALSE(s.failed);
  }
  const fs::path csv = b / "timeseries.csv";
  EXPECT_NEAR(csv_value(csv, 0, "t"), 0.04, 1e-12);
  // The same shape (to the NB=6 interpolation error), the source's volume drift removed.
  EXPECT_NEAR(csv_value(csv, 0, "D"), csv_value(a / "timeseries.csv", last_a, "D"), 2e-4);
  EXPECT_NEAR(csv_value(csv, 0, "L"), csv_value(a / "timeseries.csv", last_a, "L"), 2e-4);
  EXPECT_LT(std::abs(csv_value(csv, 0, "volume_drift")), 1e-13);
  // The Ca schedule starts at the source's time: its first segment holds Ca = 0.2 until t = 0.06.
  EXPECT_DOUBLE_EQ(csv_value(csv, 0, "ca"), 0.2);
  const std::string events = test::read_file(b / "events.jsonl");
  EXPECT_NE(events.find("\"event\":\"start_from\""), std::string::npos);
  EXPECT_NE(events.find("\"source_nb\":6"), std::string::npos);
  // Keeping the volume: the first row shows the drift the event reports.
  const fs::path c = test::fresh_dir("start_keep");
  control::ControlOptions oc = ob;
  oc.output.dir = c.string();
  oc.start.restore_volume = false;
  { app::Simulation sim(oc, ""); }
  const std::string ev = test::read_file(c / "events.jsonl");
  EXPECT_NE(ev.find("\"restore_volume\":false"), std::string::npos);
  // Onto the parallelepiped division (mesh.division box): the same shape, the division kept in
  // the checkpoint, and the run resumes on it.
  auto onto = [&](const char* name, const control::MeshOptions& mesh, int64_t code) {
    const fs::path dir = test::fresh_dir(name);
    control::ControlOptions o = ob;
    o.output.dir = dir.string();
    o.mesh = mesh;
    {
      app::Simulation sim(o, "");
      EXPECT_EQ(sim.run().steps, 5) << name;
    }
    EXPECT_NEAR(csv_value(dir / "timeseries.csv", 0, "D"),
                csv_value(a / "timeseries.csv", last_a, "D"), 2e-4)
        << name;
    EXPECT_EQ(output::Checkpoint::read(app::Simulation::latest_checkpoint(dir.string()))
                  .integer("division"),
              code)
        << name;
    app::ResumeOverrides ov;
    ov.t_end = 0.07;
    EXPECT_EQ(app::Simulation::resume(dir.string(), ov)->run().steps, 7) << name;
    return dir;
  };
  const fs::path d = onto("start_box", {10, 8, geometry::Division::Box}, 1);
  // Onto the turned cube (mesh.division diagonal, NE=6): the same, with its division.
  const fs::path g = onto("start_diagonal", {6, 8, geometry::Division::Diagonal}, 2);
  fs::remove_all(a);
  fs::remove_all(b);
  fs::remove_all(c);
  fs::remove_all(d);
  fs::remove_all(g);
}

TEST(StartFrom, ARunWithAnotherViscosityRatioGoesOnFromTheShape) {
  // Run a (lambda = 1) deforms the sphere; b starts from it with lambda = 5 on the same mesh, c
  // with lambda = 1. Both begin at a's shape; while Ca ramps up, the more viscous inside deforms
  // more slowly; b keeps lambda = 5 in its checkpoint and resumes with it.
  const fs::path a = test::fresh_dir("start_l1"), b = test::fresh_dir("start_l5"),
                 c = test::fresh_dir("start_l1_on");
  {
    app::Simulation sim(options(a, 0.04), "");
    ASSERT_EQ(sim.run().steps, 10);
  }
  const size_t last_a = test::lines_of(a / "timeseries.csv").size() - 2;
  for (const auto& [dir, lambda] : {std::pair{b, 5.0}, std::pair{c, 1.0}}) {
    control::ControlOptions o = options(dir, 0.08, lambda);
    o.start.from = a.string();
    app::Simulation sim(o, "");
    const app::RunSummary s = sim.run();
    EXPECT_EQ(s.steps, 10) << lambda;  // from t = 0.04 to 0.08
    EXPECT_FALSE(s.failed) << lambda;
    EXPECT_NEAR(csv_value(dir / "timeseries.csv", 0, "D"),
                csv_value(a / "timeseries.csv", last_a, "D"), 1e-6)
        << lambda;
  }
  const size_t last = test::lines_of(b / "timeseries.csv").size() - 2;
  const double d_a = csv_value(a / "timeseries.csv", last_a, "D");
  const double d_b = csv_value(b / "timeseries.csv", last, "D");
  const double d_c = csv_value(c / "timeseries.csv", last, "D");
  EXPECT_GT(d_b, d_a);
  EXPECT_LT(d_b, d_c);
  const output::Checkpoint ck =
      output::Checkpoint::read(app::Simulation::latest_checkpoint(b.string()));
  EXPECT_NE(ck.text("control").find("\"viscosity_ratio\": 5"), std::string::npos);
  EXPECT_TRUE(ck.has("krylov_warm"));
  app::ResumeOverrides ov;
  ov.t_end = 0.088;
  EXPECT_EQ(app::Simulation::resume(b.string(), ov)->run().steps, 12);
  fs::remove_all(a);
  fs::remove_all(b);
  fs::remove_all(c);
}

TEST(StartFrom, MissingSourcesAreRefusedNamingTheField) {
  const fs::path d = test::fresh_dir("start_bad"), empty = test::fresh_dir("start_empty");
  auto message = [&](const std::string& from) {
    control::ControlOptions o = options(d, 0.04);
    o.start.from = from;
    try {
      app::Simulation sim(o, "");
    } catch (const app::UserError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message((empty / "nowhere").string()).find("start.from: "), std::string::npos);
  EXPECT_NE(message((empty / "nowhere").string()).find("no such run directory"), std::string::npos);
  EXPECT_NE(message(empty.string()).find("no checkpoint in checkpoints/"), std::string::npos);
  // This run's own directory (or a checkpoint in it) is refused before its outputs are touched.
  test::write_file(d / "timeseries.csv", "keep");
  EXPECT_NE(message(d.string()).find("this run's own directory"), std::string::npos);
  EXPECT_NE(message((d / "checkpoints" / "ckpt_0000000010.ckpt").string()).find("own directory"),
            std::string::npos);
  EXPECT_EQ(test::read_file(d / "timeseries.csv"), "keep");
  test::write_file(empty / "x.ckpt", "garbage");
  EXPECT_NE(message((empty / "x.ckpt").string()).find("not a capflow checkpoint"),
            std::string::npos);
  fs::remove_all(d);
  fs::remove_all(empty);
}
