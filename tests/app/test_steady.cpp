// capflow steady (app/steady_run.h): a CI-sized steady state agrees with the time march to the
// march's steady tolerance and a march started from it stays there; rotational flows and ramps
// are refused; levels from steps.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "app/errors.h"
#include "app/run_directory.h"
#include "app/simulation.h"
#include "app/steady_run.h"
#include "control/control_file.h"
#include "process_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {

control::ControlOptions parse(const std::string& text, const fs::path& dir) {
  control::ParsedControl p = control::parse_control(text);
  p.options.output.dir = dir.string();
  return p.options;
}

const char* const kCase = R"({"capsule": {"law": "skalak", "C": 1},
  "mesh": {"elements": 6, "nb": 8, "division": "diagonal"}, "flow": {"type": "planar-extension"},
  "ca": 0.3, "output": {"csv_every": 0.5, "mp4": false}})";

}  // namespace

TEST(Steady, AgreesWithTheTimeMarchAndAMarchFromItStaysThere) {
  const fs::path ds = test::fresh_dir("steady_solve"), dm = test::fresh_dir("steady_march"),
                 dr = test::fresh_dir("steady_restart");
  const app::SteadySummary s = app::run_steady(parse(kCase, ds), false);
  ASSERT_EQ(s.states, 1) << s.failure;
  ASSERT_EQ(s.exit_code(), 0);
  const double D = test::csv_column(ds / "steady.csv", "D").at(0);
  const double L = test::csv_column(ds / "steady.csv", "L").at(0);
  const double residual = test::csv_column(ds / "steady.csv", "residual").at(0);
  EXPECT_LE(residual, 1e-7);  // the default steady.solve_tolerance, reported
  EXPECT_GT(test::csv_column(ds / "steady.csv", "newton").at(0), 0);

  // The time march (default adaptive steps) to its steady state.
  control::ControlOptions m = parse(kCase, dm);
  m.steady.stop = true;
  m.time.t_end = 40;
  {
    app::Simulation sim(m, "");
    const app::RunSummary r = sim.run();
    ASSERT_EQ(r.steady_states, 1) << r.reason;
    std::printf("steady: D %.7f L %.7f; march (steady test at t = %.2f): D %.7f L %.7f\n", D, L,
                r.t, r.D, r.L);
    // The march stops when |dL/dt| etc. < 1e-4 over its window: it is that close to the root.
    EXPECT_NEAR(r.D, D, 2e-4);
    EXPECT_NEAR(r.L, L, 2e-4);
  }
  // Started from the steady state, a march stays within the steady tolerance of it.
  control::ControlOptions r = parse(kCase, dr);
  r.start.from = ds.string();
  r.time.t_end = 3.0;
  app::Simulation sim(r, "");
  const app::RunSummary e = sim.run();
  ASSERT_FALSE(e.failed) << e.failure;
  const std::vector<double> Ls = test::csv_column(dr / "timeseries.csv", "L");
  const std::vector<double> ts = test::csv_column(dr / "timeseries.csv", "t");
  for (size_t i = 1; i < Ls.size(); ++i)
    EXPECT_LE(std::abs(Ls[i] - L) / (ts[i] - ts[0]), 1e-4) << "t = " << ts[i];
  fs::remove_all(ds);
  fs::remove_all(dm);
  fs::remove_all(dr);
}

TEST(Steady, RotationalFlowsAndRampsAreRefused) {
  const fs::path d = test::fresh_dir("steady_refused");
  const std::string shear = R"({"mesh": {"elements": 6, "nb": 6}, "flow": {"type": "simple-shear"},
    "ca": 0.3})";
  try {
    app::run_steady(parse(shear, d), false);
    FAIL() << "simple shear accepted";
  } catch (const app::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("tank-treading"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("capflow run"), std::string::npos) << e.what();
  }
  const std::string ramp = R"({"mesh": {"elements": 6, "nb": 6},
    "ca": [{"ca": 0.1, "hold": "steady"}, {"ramp": {"to": 0.3, "rate": 0.1}}]})";
  try {
    app::run_steady(parse(ramp, d), false);
    FAIL() << "ramp accepted";
  } catch (const app::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("ramp"), std::string::npos) << e.what();
  }
  // Through the executable: exit 2 with the message.
  const fs::path ctl = d / "shear.json";
  test::write_file(ctl, shear);
  EXPECT_EQ(test::run_capflow({CAPFLOW_EXE, "steady", ctl.string(), "-o", (d / "o").string()},
                              d / "log", 60),
            2);
  fs::remove_all(d);
}

TEST(Steady, StepsGiveOneStateAndOneCheckpointPerLevel) {
  const fs::path d = test::fresh_dir("steady_steps");
  const app::SteadySummary s = app::run_steady(
      parse(R"({"capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 6,
        "division": "diagonal"}, "ca": [{"ca": 0.3}, {"steps": {"to": 0.4, "by": 0.05}}],
        "output": {"mp4": false}})",
            d),
      false);
  ASSERT_EQ(s.states, 3) << s.failure;
  const std::vector<double> ca = test::csv_column(d / "steady.csv", "ca");
  const std::vector<double> D = test::csv_column(d / "steady.csv", "D");
  ASSERT_EQ(ca.size(), 3u);
  EXPECT_DOUBLE_EQ(ca[0], 0.3);
  EXPECT_DOUBLE_EQ(ca[1], 0.35);
  EXPECT_DOUBLE_EQ(ca[2], 0.4);
  EXPECT_LT(D[0], D[1]);  // stronger flow, longer capsule
  EXPECT_LT(D[1], D[2]);
  EXPECT_EQ(app::RunDirectory::checkpoints(d).size(), 3u);
  fs::remove_all(d);
}

TEST(Steady, AContinuationFollowsTheBranchToTheEndOfItsRange) {
  const fs::path dc = test::fresh_dir("steady_branch"), dl = test::fresh_dir("steady_level");
  const std::string branch = R"({"capsule": {"law": "skalak", "C": 1},
    "mesh": {"elements": 6, "nb": 8, "division": "diagonal"}, "flow": {"type": "planar-extension"},
    "ca": {"continuation": {"from": 0.3, "to": 0.5, "step": 0.1}}, "output": {"mp4": false}})";
  const app::SteadySummary s = app::run_steady(parse(branch, dc), false);
  ASSERT_EQ(s.exit_code(), 0) << s.failure;
  ASSERT_GE(s.states, 3);
  EXPECT_FALSE(s.fold_ca.has_value());  // the Skalak branch rises monotonically here
  const std::vector<double> ca = test::csv_column(dc / "steady.csv", "ca");
  const std::vector<double> residual = test::csv_column(dc / "steady.csv", "residual");
  const std::vector<double> folds = test::csv_column(dc / "steady.csv", "folds");
  EXPECT_EQ(folds.size(), ca.size());  // the column is there, for every state
  for (double f : folds) EXPECT_EQ(f, 0);
  for (const auto& e : test::events(dc)) EXPECT_NE(e["event"], "warning") << e.dump();
  ASSERT_EQ(ca.size(), static_cast<size_t>(s.states));
  EXPECT_EQ(ca.front(), 0.3);
  EXPECT_EQ(ca.back(), 0.5);  // the last state lands on the end of the range
  for (size_t k = 0; k < ca.size(); ++k) {
    EXPECT_LE(residual[k], 1e-7) << k;
    if (k) {
      EXPECT_GT(ca[k], ca[k - 1]);
    }
    if (k) {
      EXPECT_LE(ca[k] - ca[k - 1], 0.1 + 1e-12);
    }
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dc / "checkpoints"), fs::directory_iterator{}),
            s.states);
  // The branch's last state is the root a solve at Ca = 0.5 finds (both to residual 1e-7).
  const std::string level = R"({"capsule": {"law": "skalak", "C": 1},
    "mesh": {"elements": 6, "nb": 8, "division": "diagonal"}, "flow": {"type": "planar-extension"},
    "ca": 0.5, "output": {"mp4": false}})";
  ASSERT_EQ(app::run_steady(parse(level, dl), false).states, 1);
  EXPECT_NEAR(test::csv_column(dl / "steady.csv", "D").at(0),
              test::csv_column(dc / "steady.csv", "D").back(), 1e-6);
  EXPECT_NEAR(test::csv_column(dl / "steady.csv", "L").at(0),
              test::csv_column(dc / "steady.csv", "L").back(), 1e-6);
  // capflow run refuses a continuation (exit 2, naming capflow steady).
  const fs::path ctl = dc / "branch.json";
  test::write_file(ctl, branch);
  EXPECT_EQ(test::run_capflow({CAPFLOW_EXE, "run", ctl.string(), "-o", (dc / "run").string()},
                              dc / "log", 60),
            2);
  EXPECT_NE(test::read_file(dc / "log").find("capflow steady"), std::string::npos);
  fs::remove_all(dc);
  fs::remove_all(dl);
}

namespace {

std::string live_case(const std::string& ca, const std::string& extra = "") {
  return R"({"capsule": {"law": "skalak", "C": 1},
    "mesh": {"elements": 6, "nb": 8, "division": "diagonal"}, "flow": {"type": "planar-extension"},
    "output": {"mp4": false}, "ca": )" +
         ca + extra + "}";
}

void save(const fs::path& ctl, const std::string& text) {
  const fs::path tmp = ctl.string() + ".new";
  test::write_file(tmp, text);
  fs::rename(tmp, ctl);
}

}  // namespace

TEST(Steady, TheLiveControlFilePausesRefusesShortensAndStops) {
  const fs::path d = test::fresh_dir("steady_live");
  const fs::path ctl = d / "control.json", run = d / "run";
  const std::string branch = R"({"continuation": {"from": 0.3, "to": 2.0, "step": 0.1}})";
  save(ctl, live_case(branch));
  pid_t pid =
      test::spawn({CAPFLOW_EXE, "steady", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "steady.csv") >= 2; }, 120))
      << test::read_file(d / "stderr.log");
  // Paused: no state is added until "running" is saved.
  save(ctl, live_case(branch, R"(, "run": {"state": "paused"})"));
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "pause") == 1; }, 60))
      << test::read_file(d / "stderr.log");
  const long rows = test::csv_rows(run / "steady.csv");
  // A broken edit while paused is refused; the run keeps its settings.
  save(ctl, "{\"ca\": ");
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "edit") >= 2; }, 20));
  std::this_thread::sleep_for(std::chrono::seconds(2));
  EXPECT_EQ(test::csv_rows(run / "steady.csv"), rows);
  bool refused = false;
  for (const auto& e : test::events(run))
    if (e["event"] == "edit" && !e["accepted"].get<bool>()) refused = true;
  EXPECT_TRUE(refused);
  // The range shortened (and a key steady does not use refused), then resumed: the branch ends
  // on the new end.
  save(ctl, live_case(R"({"continuation": {"from": 0.3, "to": 0.9, "step": 0.1}})",
                      R"(, "steady": {"window": 2})"));
  ASSERT_EQ(test::wait_exit(pid, 180), 0) << test::read_file(d / "stderr.log");
  EXPECT_EQ(test::count_events(run, "continue"), 1);
  EXPECT_EQ(test::csv_column(run / "steady.csv", "ca").back(), 0.9);
  nlohmann::json last_edit;
  for (const auto& e : test::events(run))
    if (e["event"] == "edit" && e["accepted"].get<bool>()) last_edit = e;
  EXPECT_TRUE(last_edit["applied"].contains("ca")) << last_edit.dump();
  EXPECT_NE(last_edit["refused"]["steady.window"].dump().find("does not use"), std::string::npos)
      << last_edit.dump();

  // "stopped" ends the branch at once (during a Newton solve), keeping the states found.
  const fs::path run2 = d / "run2";
  save(ctl, live_case(branch));
  pid = test::spawn({CAPFLOW_EXE, "steady", ctl.string(), "-o", run2.string()}, d / "stderr2.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run2 / "steady.csv") >= 1; }, 120));
  save(ctl, live_case(branch, R"(, "run": {"state": "stopped"})"));
  EXPECT_EQ(test::wait_exit(pid, 30), 0) << test::read_file(d / "stderr2.log");
  EXPECT_EQ(test::count_events(run2, "end"), 1);
  EXPECT_LT(test::csv_column(run2 / "steady.csv", "ca").back(), 2.0);
  fs::remove_all(d);
}

TEST(Steady, OneFramePerSteadyState) {
  const fs::path d = test::fresh_dir("steady_frames");
  control::ControlOptions o = parse(
      live_case(R"([{"ca": 0.3}, {"ca": 0.4}])", R"(, "render": {"width": 160, "height": 120})"),
      d);
  o.output.png = true;
  o.output.mp4.enabled = true;
  const app::SteadySummary s = app::run_steady(o, false);
  ASSERT_EQ(s.exit_code(), 0) << s.failure;
  ASSERT_EQ(s.states, 2);
  EXPECT_TRUE(fs::exists(d / "frames" / "frame_000000.png"));
  EXPECT_TRUE(fs::exists(d / "frames" / "frame_000001.png"));
  EXPECT_FALSE(fs::exists(d / "frames" / "frame_000002.png"));
  EXPECT_GT(fs::file_size(d / "movie.mp4"), 0u);
  fs::remove_all(d);
}

TEST(Steady, ACompressedRootIsReportedWithAWarning) {
  // Skalak C=1 at Ca = 0.07 (NE=6 NB=8): a root exists, with compressive tension near the
  // equator (the membrane would wrinkle: no bending stiffness).
  const fs::path d = test::fresh_dir("steady_compressed");
  const app::SteadySummary s = app::run_steady(parse(live_case("0.07"), d), false);
  ASSERT_EQ(s.states, 1) << s.failure;
  EXPECT_LT(test::csv_column(d / "steady.csv", "tau_min").at(0), 0);
  bool warned = false;
  for (const auto& e : test::events(d))
    if (e["event"] == "warning" && e["cause"] == "compression") warned = true;
  EXPECT_TRUE(warned);
  fs::remove_all(d);
}

TEST(Steady, AnEditOfTheLevelsReplacesTheLevelsToCome) {
  const fs::path d = test::fresh_dir("steady_levels_edit");
  const fs::path ctl = d / "control.json", run = d / "run";
  save(ctl,
       live_case("[{\"ca\": 0.3}, {\"ca\": 0.35}, {\"ca\": 0.4}, {\"ca\": 0.45}, {\"ca\": 0.5}]"));
  const pid_t pid =
      test::spawn({CAPFLOW_EXE, "steady", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "steady.csv") >= 1; }, 120))
      << test::read_file(d / "stderr.log");
  // Paused between two states, then the edit: levels 0.4 and 0.45 dropped, 0.33 inserted (the
  // levels beyond the last one solved: 0.33 follows 0.3, or is skipped after 0.35).
  const std::string levels =
      "[{\"ca\": 0.3}, {\"ca\": 0.35}, {\"ca\": 0.4}, {\"ca\": 0.45}, {\"ca\": 0.5}]";
  save(ctl, live_case(levels, R"(, "run": {"state": "paused"})"));
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "pause") == 1; }, 60))
      << test::read_file(d / "stderr.log");
  save(ctl, live_case("[{\"ca\": 0.3}, {\"ca\": 0.33}, {\"ca\": 0.5}]"));
  ASSERT_EQ(test::wait_exit(pid, 180), 0) << test::read_file(d / "stderr.log");
  const std::vector<double> ca = test::csv_column(run / "steady.csv", "ca");
  ASSERT_GE(ca.size(), 3u);
  EXPECT_EQ(ca.front(), 0.3);
  EXPECT_EQ(ca.back(), 0.5);
  for (size_t k = 1; k < ca.size(); ++k) EXPECT_GT(ca[k], ca[k - 1]);
  for (double c : ca) {
    EXPECT_NE(c, 0.4);
    EXPECT_NE(c, 0.45);
  }
  EXPECT_EQ(ca.size(), 3u);  // 0.3, then 0.33 or 0.35, then 0.5
  fs::remove_all(d);
}
