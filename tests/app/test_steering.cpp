// Live steering and signals, through the capflow executable:
//  * an in-place rewrite and a rename-save of the control file change Ca from the logged
//    simulated time on (checked in timeseries.csv and events.jsonl);
//  * an invalid edit is refused, logged, and leaves the run unharmed;
//  * SIGINT finishes the step, writes a checkpoint and a playable movie.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cstdio>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "process_util.h"

using namespace capflow;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using test::count_events;
using test::csv_rows;
using test::events;
using test::spawn;
using test::wait_exit;

std::string control(double ca, const std::string& extra = "", const std::string& numerics = "") {
  return R"({"capsule": {"law": "skalak"}, "mesh": {"elements": 6, "nb": 6},
    "time": {"dt": 0.002, "t_end": 1000}, "ca": )" + std::to_string(ca) +
         R"(, "output": {"dir": "run", "csv_every": 0.002}, "numerics": {"threads": 1)" + numerics + "}" + extra + "}";
}

}  // namespace

TEST(Steering, EditsChangeCaFromTheLoggedTimeAndBadEditsAreHarmless) {
  const fs::path d = test::fresh_dir("steer");
  const fs::path ctl = d / "control.json", run = d / "run";
  test::write_file(ctl, control(0.3));
  const pid_t pid = spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return csv_rows(run / "timeseries.csv") >= 5; }, 60));

  // 1. In-place rewrite.
  test::write_file(ctl, control(0.5));
  ASSERT_TRUE(test::wait_for([&] { return count_events(run, "edit") >= 1; }, 10)) << test::read_file(d / "stderr.log");
  // 2. Invalid edit: refused and logged; the run goes on.
  test::write_file(ctl, R"({"ca": -1, "mesh": {"elements": 6, "nb": 6}})");
  ASSERT_TRUE(test::wait_for([&] { return count_events(run, "edit") >= 2; }, 10));
  const long rows_after_bad = csv_rows(run / "timeseries.csv");
  ASSERT_TRUE(test::wait_for([&] { return csv_rows(run / "timeseries.csv") > rows_after_bad + 3; }, 30));
  // 3. Rename-save (write a temporary file, rename it over the control file).
  test::write_file(d / "control.json.new", control(0.7));
  fs::rename(d / "control.json.new", ctl);
  ASSERT_TRUE(test::wait_for([&] { return count_events(run, "edit") >= 3; }, 10));
  const long rows_after_rename = csv_rows(run / "timeseries.csv");
  ASSERT_TRUE(test::wait_for([&] { return csv_rows(run / "timeseries.csv") > rows_after_rename + 3; }, 30));
  // 4. Stop through the control file.
  test::write_file(ctl, control(0.7, R"(, "run": {"state": "stopped"})"));
  EXPECT_EQ(wait_exit(pid, 30), 0) << test::read_file(d / "stderr.log");

  std::vector<json> edits;
  for (const auto& e : events(run))
    if (e["event"] == "edit") edits.push_back(e);
  ASSERT_GE(edits.size(), 4u);
  EXPECT_TRUE(edits[0]["accepted"].get<bool>());
  EXPECT_FALSE(edits[1]["accepted"].get<bool>());
  EXPECT_NE(edits[1]["errors"].dump().find("ca"), std::string::npos);
  EXPECT_TRUE(edits[2]["accepted"].get<bool>());
  const double t1 = edits[0]["t"], t3 = edits[2]["t"];
  ASSERT_LT(t1, t3);
  // Ca in the time series follows the edits from the logged times on.
  int checked = 0;
  for (const auto& l : test::lines_of(run / "timeseries.csv")) {
    if (l[0] == 't') continue;
    double t, ca;
    ASSERT_EQ(std::sscanf(l.c_str(), "%lf,%lf", &t, &ca), 2);
    const double expect = t <= t1 + 1e-12 ? 0.3 : (t <= t3 + 1e-12 ? 0.5 : 0.7);
    EXPECT_NEAR(ca, expect, 1e-12) << "t = " << t;
    ++checked;
  }
  EXPECT_GT(checked, 15);
  // The effective control file holds the last accepted Ca.
  EXPECT_NE(test::read_file(run / "control.json").find("0.7"), std::string::npos);
  fs::remove_all(d);
}

// A live edit of numerics.volume_correction reaches the dynamics: from the next step on the
// shape is rescaled to the initial volume (paper eq. 23), so the relative volume drift of the
// time series drops from the uncorrected NB=6 leak (~1e-8 by t = 0.04) to round-off.
TEST(Steering, VolumeCorrectionSwitchedOnMidRunHoldsTheVolume) {
  const fs::path d = test::fresh_dir("steer_volume");
  const fs::path ctl = d / "control.json", run = d / "run";
  test::write_file(ctl, control(0.3));
  const pid_t pid = spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return csv_rows(run / "timeseries.csv") >= 25; }, 60));
  test::write_file(ctl, control(0.3, "", R"(, "volume_correction": true)"));
  ASSERT_TRUE(test::wait_for([&] { return count_events(run, "edit") >= 1; }, 10)) << test::read_file(d / "stderr.log");
  const long rows_after_edit = csv_rows(run / "timeseries.csv");
  ASSERT_TRUE(test::wait_for([&] { return csv_rows(run / "timeseries.csv") > rows_after_edit + 10; }, 30));
  test::write_file(ctl, control(0.3, R"(, "run": {"state": "stopped"})", R"(, "volume_correction": true)"));
  EXPECT_EQ(wait_exit(pid, 30), 0) << test::read_file(d / "stderr.log");

  double t_edit = -1;
  for (const auto& e : events(run))
    if (e["event"] == "edit" && e["accepted"].get<bool>() &&
        e["applied"].contains("numerics.volume_correction"))
      t_edit = e["t"];
  ASSERT_GT(t_edit, 0.02);
  const std::vector<std::string> lines = test::lines_of(run / "timeseries.csv");
  int col = -1, k = 0;
  std::stringstream header(lines.at(0));
  for (std::string name; std::getline(header, name, ','); ++k)
    if (name == "volume_drift") col = k;
  ASSERT_GE(col, 0);
  double before = 0, after = 0;
  int n_after = 0;
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    std::vector<double> v;
    std::stringstream row(lines[i]);
    for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
    const double t = v.at(0), drift = std::abs(v.at(col));
    if (t <= t_edit + 1e-9) before = std::max(before, drift);
    else { after = std::max(after, drift); ++n_after; }
  }
  std::printf("volume drift: max %.1e up to the edit at t = %.3f, max %.1e in the %d rows after\n",
              before, t_edit, after, n_after);
  EXPECT_GT(before, 1e-10);
  EXPECT_LT(after, 1e-12);
  EXPECT_GE(n_after, 10);
  fs::remove_all(d);
}

TEST(Signals, SigintWritesACheckpointAndAPlayableMovie) {
  const fs::path d = test::fresh_dir("sigint");
  const fs::path ctl = d / "control.json", run = d / "run";
  test::write_file(ctl, R"({"mesh": {"elements": 6, "nb": 6}, "time": {"dt": 0.004, "t_end": 1000},
    "ca": 0.4, "output": {"csv_every": 0.04, "frame_every": 0.008, "png": false,
    "mp4": {"fps": 10}}, "render": {"width": 160, "height": 120, "msaa": 0},
    "numerics": {"threads": 1}})");
  const pid_t pid = spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "stderr.log");
  ASSERT_TRUE(test::wait_for([&] { return csv_rows(run / "timeseries.csv") >= 3; }, 60))
      << test::read_file(d / "stderr.log");
  kill(pid, SIGINT);
  EXPECT_EQ(wait_exit(pid, 60), 0) << test::read_file(d / "stderr.log");
  const std::string log = test::read_file(d / "stderr.log");
  EXPECT_NE(log.find("stopped by signal"), std::string::npos) << log;
  bool has_ckpt = false;
  for (const auto& e : fs::directory_iterator(run / "checkpoints")) has_ckpt |= e.path().extension() == ".ckpt";
  EXPECT_TRUE(has_ckpt);
  // ffprobe: h264, yuv420p, and as many frames as the renderer reported.
  const std::string probe = (d / "probe.txt").string();
  const std::string cmd = "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                          "stream=codec_name,pix_fmt,nb_read_frames -of default=nw=1 " +
                          (run / "movie.mp4").string() + " > " + probe + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << test::read_file(probe);
  const std::string p = test::read_file(probe);
  EXPECT_NE(p.find("codec_name=h264"), std::string::npos) << p;
  EXPECT_NE(p.find("pix_fmt=yuv420p"), std::string::npos) << p;
  const auto pos = log.find("renderer: ");
  ASSERT_NE(pos, std::string::npos) << log;
  const long written = std::atol(log.c_str() + pos + 10);
  EXPECT_GT(written, 0);
  EXPECT_NE(p.find("nb_read_frames=" + std::to_string(written)), std::string::npos) << p << log;
  fs::remove_all(d);
}

TEST(CommandLine, BadOptionValuesExitWithInvalidInput) {
  const fs::path dir = test::fresh_dir("cli");
  const fs::path control = dir / "c.json";
  {
    std::ofstream f(control);
    f << R"({"ca": 0.3, "mesh": {"elements": 6, "nb": 6}, "time": {"dt": 0.01, "t_end": 0.02}})";
  }
  for (const char* bad : {"0", "-1", "abc", "2e6"}) {
    const fs::path log = dir / "err.txt";
    const pid_t pid = spawn({CAPFLOW_EXE, "run", control.string(), "--t-end", bad, "-o",
                             (dir / "run").string()},
                            log);
    EXPECT_EQ(wait_exit(pid, 60), 2) << bad;
    const std::string err = test::read_file(log);
    EXPECT_NE(err.find("--t-end"), std::string::npos) << err;
    EXPECT_NE(err.find("(0, 1e6]"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "run")) << "a refused command line must not create the run";
  }
}
