// Steering regressions of Milestone 7, through the capflow executable and the Simulation API:
//  * steady.csv and the steady events carry the Ca that was held (not the next level's) and the
//    time the steady test fired;
//  * editing the running ramp continues from the current Ca (no jump back), and a new schedule
//    that begins with steps steps up from where the run is;
//  * hostile live edits (deep nesting, 1e400, duplicate keys, a 2 MiB file, /dev/zero, a FIFO)
//    are refused and the run goes on;
//  * SIGHUP ends a run like SIGTERM (checkpoint, exit 0);
//  * render.msaa above what llvmpipe supports takes the largest supported count;
//  * the progress rate leaves paused time out.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "app/progress.h"
#include "app/simulation.h"
#include "control/control_file.h"
#include "process_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {

std::vector<double> column(const fs::path& csv, const std::string& name) {
  std::vector<double> out = test::csv_column(csv, name);
  EXPECT_FALSE(out.empty()) << name << " in " << csv;
  return out;
}

std::string base_control(const std::string& ca, const std::string& extra = "") {
  return R"({"mesh": {"elements": 6, "nb": 6}, "time": {"dt": 0.002, "t_end": 1000},
    "output": {"dir": "run", "csv_every": 0.002}, "numerics": {"threads": 1}, "ca": )" +
         ca + extra + "}";
}

}  // namespace

TEST(SteeringRegression, SteadyRowsCarryTheHeldCaAndTheTime) {
  const fs::path d = test::fresh_dir("steady_ca");
  control::ControlOptions o = control::parse_control(R"({
    "mesh": {"elements": 6, "nb": 6}, "time": {"dt": 0.004, "t_end": 2},
    "ca": [{"ca": 0.1, "hold": "steady"}, {"steps": {"to": 0.4, "by": 0.1, "hold": "steady"}}],
    "steady": {"window": 0.02, "min_hold": 0.02, "tolerance": 1.0, "stop": true},
    "output": {"csv_every": 0.004}, "numerics": {"threads": 1}})")
                                  .options;
  o.output.dir = d.string();
  app::Simulation sim(o, "");
  const app::RunSummary s = sim.run();
  EXPECT_EQ(s.steady_states, 4);
  const std::vector<double> t = column(d / "steady.csv", "t"), ca = column(d / "steady.csv", "ca");
  ASSERT_EQ(ca.size(), 4u);
  const double held[] = {0.1, 0.2, 0.3, 0.4};
  for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(ca[k], held[k], 1e-12) << k;
  // The timeseries row at each steady time shows the same Ca; so does the steady event.
  const std::vector<double> ts = column(d / "timeseries.csv", "t"),
                            tca = column(d / "timeseries.csv", "ca");
  for (size_t k = 0; k < t.size(); ++k)
    for (size_t i = 0; i < ts.size(); ++i)
      if (std::abs(ts[i] - t[k]) < 1e-9) {
        EXPECT_NEAR(tca[i], ca[k], 1e-12) << "t = " << t[k];
      }
  int steady_events = 0;
  for (const auto& e : test::events(d))
    if (e["event"] == "steady") {
      EXPECT_NEAR(e["ca"].get<double>(), held[steady_events], 1e-12);
      EXPECT_NEAR(e["t"].get<double>(), t[steady_events], 1e-9);
      EXPECT_EQ(e["message"].get<std::string>().find("Ca ->"), std::string::npos);
      ++steady_events;
    }
  EXPECT_EQ(steady_events, 4);
  fs::remove_all(d);
}

TEST(SteeringRegression, RampEditContinuesAndNewStepsStartFromTheCurrentCa) {
  const fs::path d = test::fresh_dir("ramp_edit");
  const fs::path ctl = d / "control.json", run = d / "run";
  const std::string hold = R"([{"ca": 0.3, "hold": 0.02}, {"ramp": {"to": 5, "rate": )";
  test::write_file(ctl, base_control(hold + "0.5}}]"));
  const pid_t pid =
      test::spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= 30; }, 60));
  // 1. Only the ramp's rate changes.
  test::write_file(ctl, base_control(hold + "0.25}}]"));
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "edit") >= 1; }, 20))
      << test::read_file(d / "stderr.log");
  const long rows1 = test::csv_rows(run / "timeseries.csv");
  ASSERT_TRUE(
      test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") > rows1 + 20; }, 30));
  // 2. A new schedule that begins with steps: up by 0.5 from where the run is.
  test::write_file(ctl, base_control(R"([{"steps": {"to": 10, "by": 0.5, "hold": 100}}])"));
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "edit") >= 2; }, 20));
  const long rows2 = test::csv_rows(run / "timeseries.csv");
  ASSERT_TRUE(
      test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") > rows2 + 5; }, 30));
  test::write_file(ctl, base_control(R"([{"steps": {"to": 10, "by": 0.5, "hold": 100}}])",
                                     R"(, "run": {"state": "stopped"})"));
  EXPECT_EQ(test::wait_exit(pid, 30), 0) << test::read_file(d / "stderr.log");

  std::vector<nlohmann::json> edits;
  for (const auto& e : test::events(run))
    if (e["event"] == "edit") edits.push_back(e);
  ASSERT_GE(edits.size(), 2u);
  for (const auto& e : edits) {
    EXPECT_TRUE(e["accepted"].get<bool>());
    EXPECT_TRUE(e["refused"].empty()) << e.dump();  // -o is not an edit of output.dir
  }
  const double t1 = edits[0]["t"], t2 = edits[1]["t"], ca2 = edits[1]["ca"];
  const std::vector<double> t = column(run / "timeseries.csv", "t"),
                            ca = column(run / "timeseries.csv", "ca");
  double ca_at_t2 = -1;
  for (size_t i = 1; i < t.size(); ++i) {
    if (t[i] <= t2 + 1e-12) {
      // up to the steps edit Ca never falls, and it moves at the rate in force
      EXPECT_GE(ca[i], ca[i - 1] - 1e-12) << "t = " << t[i];
      if (t[i - 1] > 0.02 + 1e-9) {
        const double rate = (ca[i] - ca[i - 1]) / (t[i] - t[i - 1]);
        EXPECT_NEAR(rate, t[i] <= t1 + 1e-12 ? 0.5 : 0.25, 1e-6) << "t = " << t[i];
      }
      ca_at_t2 = ca[i];
    } else {
      EXPECT_NEAR(ca[i], ca_at_t2 + 0.5, 1e-9) << "t = " << t[i];  // one step up, from here
    }
  }
  EXPECT_NEAR(ca2, ca_at_t2 + 0.5, 1e-9);
  EXPECT_GT(ca_at_t2, 0.3 + 0.25 * (t2 - 0.02) - 1e-9);  // the first hold was not replayed
  fs::remove_all(d);
}

TEST(SteeringRegression, HostileLiveEditsAreRefusedAndTheRunGoesOn) {
  const fs::path d = test::fresh_dir("hostile_edit");
  const fs::path ctl = d / "control.json", run = d / "run";
  test::write_file(ctl, base_control("0.3"));
  const pid_t pid =
      test::spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= 5; }, 60));
  auto replace_with = [&](const std::function<void(const fs::path&)>& make) {
    const fs::path tmp = d / "next";
    fs::remove(tmp);
    make(tmp);
    fs::rename(tmp, ctl);
  };
  const std::string deep = "{\"ca\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  std::vector<std::function<void(const fs::path&)>> edits = {
      [&](const fs::path& p) { test::write_file(p, deep); },
      [&](const fs::path& p) { test::write_file(p, base_control("1e400")); },
      [&](const fs::path& p) { test::write_file(p, base_control("0.4, \"ca\": 0.5")); },
      [&](const fs::path& p) {
        test::write_file(
            p, base_control("0.4, \"description\": \"" + std::string(2 << 20, 'x') + "\""));
      },
      [&](const fs::path& p) { fs::create_symlink("/dev/zero", p); },
      [&](const fs::path& p) { ASSERT_EQ(::mkfifo(p.c_str(), 0644), 0); },
  };
  const char* expect[] = {"nested deeper", "outside the range of a double",
                          "given twice",   "larger than 1 MiB",
                          "is a device",   "is a FIFO"};
  for (size_t k = 0; k < edits.size(); ++k) {
    replace_with(edits[k]);
    ASSERT_TRUE(test::wait_for(
        [&] { return test::count_events(run, "edit") >= static_cast<int>(k + 1); }, 20))
        << k << test::read_file(d / "stderr.log");
    const long rows = test::csv_rows(run / "timeseries.csv");
    ASSERT_TRUE(
        test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") > rows + 3; }, 30))
        << k;
    nlohmann::json e;
    for (const auto& ev : test::events(run))
      if (ev["event"] == "edit") e = ev;
    EXPECT_FALSE(e["accepted"].get<bool>()) << k;
    EXPECT_NE(e["errors"].dump().find(expect[k]), std::string::npos)
        << k << " " << e.dump().substr(0, 300);
  }
  // A continuation is capflow steady's: the edit of "ca" is refused, the run holds its Ca.
  replace_with([&](const fs::path& p) {
    test::write_file(p, base_control(R"({"continuation": {"from": 0.3, "to": 1, "step": 0.1}})"));
  });
  ASSERT_TRUE(test::wait_for(
      [&] { return test::count_events(run, "edit") >= static_cast<int>(edits.size() + 1); }, 20))
      << test::read_file(d / "stderr.log");
  nlohmann::json e;
  for (const auto& ev : test::events(run))
    if (ev["event"] == "edit") e = ev;
  EXPECT_NE(e["refused"]["ca"].dump().find("capflow steady"), std::string::npos) << e.dump();
  EXPECT_FALSE(e["applied"].contains("ca")) << e.dump();
  replace_with([&](const fs::path& p) {
    test::write_file(p, base_control("0.3", R"(, "run": {"state": "stopped"})"));
  });
  EXPECT_EQ(test::wait_exit(pid, 30), 0) << test::read_file(d / "stderr.log");
  EXPECT_EQ(test::count_events(run, "end"), 1);
  for (double ca : column(run / "timeseries.csv", "ca")) EXPECT_DOUBLE_EQ(ca, 0.3);
  fs::remove_all(d);
}

TEST(SteeringRegression, SighupStopsWithACheckpoint) {
  const fs::path d = test::fresh_dir("sighup");
  const fs::path ctl = d / "control.json", run = d / "run";
  test::write_file(ctl, base_control("0.3"));
  const pid_t pid =
      test::spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= 5; }, 60));
  kill(pid, SIGHUP);
  EXPECT_EQ(test::wait_exit(pid, 30), 0) << test::read_file(d / "stderr.log");
  bool by_signal = false;
  for (const auto& e : test::events(run))
    if (e["event"] == "checkpoint" && e["why"] == "stopped by signal") by_signal = true;
  EXPECT_TRUE(by_signal);
  fs::remove_all(d);
}

TEST(SteeringRegression, MsaaAboveTheSupportedCountUsesTheLargestSupported) {
  const fs::path d = test::fresh_dir("msaa");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, R"({"mesh": {"elements": 6, "nb": 6}, "time": {"dt": 0.004, "t_end": 0.016},
    "ca": 0.3, "output": {"csv_every": 0.004, "frame_every": 0.008, "mp4": false},
    "render": {"width": 64, "height": 48, "antialias": "msaa", "msaa": 16}, "numerics": {"threads": 1}})");
  EXPECT_EQ(
      test::run_capflow({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log"),
      0)
      << test::read_file(d / "stderr.log");
  const std::string log = test::read_file(run / "run.log");
  EXPECT_NE(log.find("render.msaa 16 is above what this GL supports"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(run / "frames" / "frame_000002.png"));
  fs::remove_all(d);
}

TEST(Progress, PausedTimeIsLeftOutOfTheRate) {
  double now = 100;
  app::Progress p(false, [&] { return now; });
  p.start(10);
  now += 2;  // 20 steps in 2 s
  p.pause();
  now += 50;  // paused
  p.unpause();
  now += 2;  // 20 more in 2 s
  EXPECT_DOUBLE_EQ(p.rate(50), 10.0);
  p.pause();
  now += 7;
  EXPECT_DOUBLE_EQ(p.rate(50), 10.0);  // the clock stands while paused
  EXPECT_TRUE(p.due());
  EXPECT_FALSE(p.due());  // logs: every 10 s
  now += 10;
  EXPECT_TRUE(p.due());
}
