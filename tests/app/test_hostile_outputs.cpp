// The second hostile-input round (Milestone 17), outputs and faults: a run's console cannot kill
// it, a stop is honoured, a full disk or a kill leaves files a resume continues bit for bit (no
// gap in the frames, a playable movie, a torn CSV row kept aside), nothing of the user's is
// overwritten, and every command's output failure exits 5 naming the file.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "../output/ffprobe_util.h"
#include "hostile_util.h"

using namespace capflow;
using test::contains;
using test::outcome;
namespace fs = std::filesystem;

namespace {

// The frame indices of frames/ and whether they are 0..n-1 without a gap.
bool frames_without_gap(const fs::path& run, long* n) {
  std::set<long> idx;
  for (const auto& e : fs::directory_iterator(run / "frames")) {
    const std::string f = e.path().filename().string();
    if (f.rfind("frame_", 0) == 0 && e.path().extension() == ".png")
      idx.insert(std::atol(f.c_str() + 6));
  }
  *n = static_cast<long>(idx.size());
  return idx.empty() || (*idx.begin() == 0 && *idx.rbegin() == *n - 1);
}

// Waits until the run has written at least `rows` rows of timeseries.csv.
bool wait_rows(const fs::path& run, long rows, double seconds = 60) {
  return test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= rows; }, seconds);
}

}  // namespace

// `capflow run c.json 2>&1 | head -n 1` killed the run with SIGPIPE: no rows, no end, no
// checkpoint. The console is a convenience; the run directory is the record.
TEST(HostileOutputs, AClosedConsoleDoesNotStopARun) {
  const fs::path d = test::fresh_dir("console");
  test::write_file(d / "c.json", test::small_run(0.2));
  test::Limits lim;
  lim.closed_console = true;
  EXPECT_EQ(test::capflow({"run", (d / "c.json").string(), "-o", (d / "run").string()}, "", lim),
            0);
  EXPECT_EQ(test::csv_rows(d / "run" / "timeseries.csv"), 11);  // t = 0, 0.02, ..., 0.2
  EXPECT_EQ(test::count_events(d / "run", "end"), 1);
  EXPECT_TRUE(contains(test::read_file(d / "run" / "run.log"), "the console is gone"));
  EXPECT_FALSE(fs::is_empty(d / "run" / "checkpoints"));
  fs::remove_all(d);
}

// A live edit that is refused as a whole (a fixed dt of 1e-6 with t_end 50: 5e7 steps) kept
// every later edit refused too, a stop among them: the run did not stop within 60 s.
TEST(HostileOutputs, AStopIsHonouredWhenTheRestOfTheEditIsRefused) {
  const fs::path d = test::fresh_dir("stop");
  const fs::path ctl = d / "c.json", run = d / "run";
  const std::string body = R"({"mesh": {"elements": 6, "nb": 6}, "ca": 0.3, "time": {"dt": )";
  test::write_file(ctl, body + R"("auto", "t_end": 50}, "output": {"csv_every": 0.02}})");
  const pid_t pid = test::start_capflow({"run", ctl.string(), "-o", run.string()}, d / "log");
  ASSERT_TRUE(wait_rows(run, 3));
  test::write_file(ctl, body + R"(1e-6, "t_end": 50}, "output": {"csv_every": 0.02}})");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  test::write_file(ctl, body + R"(1e-6, "t_end": 50}, "output": {"csv_every": 0.02},
                                  "run": {"state": "stopped"}})");
  EXPECT_EQ(test::wait_exit(pid, 30), 0) << test::read_file(d / "log");
  const std::string log = test::read_file(d / "log");
  EXPECT_TRUE(contains(log, "run.state running -> stopped applied")) << log;
  EXPECT_TRUE(contains(log, "end (run.state is \"stopped\")")) << log;
  fs::remove_all(d);
}

// numerics.threads 1024 made libgomp end the process (exit 1) where threads could not be made;
// the count is now tried first and cut to what works, with a warning.
TEST(HostileOutputs, MoreThreadsThanTheProcessMayStartAreCut) {
  const fs::path d = test::fresh_dir("threads");
  test::write_file(d / "c.json", test::small_run(0.04, "", R"("numerics": {"threads": 1024})"));
  test::Limits lim;
  lim.address_space = 3L << 30;  // room for a few hundred 8 MiB thread stacks
  const auto o = outcome({"run", (d / "c.json").string(), "-o", (d / "run").string()}, d, lim);
  EXPECT_EQ(o.code, 0) << o.log;
  EXPECT_TRUE(contains(o.log, "numerics.threads 1024: this process can start only")) << o.log;
  // the same as a live edit
  const fs::path ctl = d / "live.json", run = d / "live";
  test::write_file(ctl, test::small_run(30, "", R"("numerics": {"threads": 1})"));
  const pid_t pid = test::start_capflow({"run", ctl.string(), "-o", run.string()}, d / "log", lim);
  ASSERT_TRUE(wait_rows(run, 2));
  test::write_file(ctl, test::small_run(30, "", R"("numerics": {"threads": 1024})"));
  ASSERT_TRUE(test::wait_for(
      [&] { return contains(test::read_file(run / "events.jsonl"), "this process can start"); },
      30));
  test::write_file(ctl, test::small_run(30, "", R"("numerics": {"threads": 1024},
                                                   "run": {"state": "stopped"})"));
  EXPECT_EQ(test::wait_exit(pid, 60), 0) << test::read_file(d / "log");
  fs::remove_all(d);
}

// capflow sweep overwrote the sweep.csv a user kept in output.dir and exited 0.
TEST(HostileOutputs, ASweepNeverReplacesTheUsersFiles) {
  const fs::path d = test::fresh_dir("sweepdir");
  const fs::path out = d / "out";
  fs::create_directories(out);
  test::write_file(out / "sweep.csv", "my,own,data\n");
  test::write_file(d / "s.json", R"({"base": {"ca": 0.3, "mesh": {"elements": 6, "nb": 6},
      "time": {"t_end": 0.02}}, "vary": {"ca": [0.2, 0.3]}, "output": {"dir": ")" +
                                     out.string() + R"("}})");
  auto o = outcome({"sweep", (d / "s.json").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "holds a sweep.csv that is not a capflow sweep's summary")) << o.log;
  o = outcome({"sweep", (d / "s.json").string(), "--overwrite"}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_EQ(test::read_file(out / "sweep.csv"), "my,own,data\n");
  // another file of the user's: refused, and with --overwrite the sweep goes beside it
  fs::rename(out / "sweep.csv", out / "notes.csv");
  o = outcome({"sweep", (d / "s.json").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "is not empty and is not a capflow sweep (it holds notes.csv)"))
      << o.log;
  o = outcome({"sweep", (d / "s.json").string(), "--overwrite"}, d);
  EXPECT_EQ(o.code, 0) << o.log;
  EXPECT_EQ(test::read_file(out / "notes.csv"), "my,own,data\n");
  EXPECT_EQ(test::csv_rows(out / "sweep.csv"), 2);
  // re-running continues the sweep (nothing to do), the user's file kept
  o = outcome({"sweep", (d / "s.json").string()}, d);
  EXPECT_EQ(o.code, 0) << o.log;
  EXPECT_TRUE(fs::exists(out / "notes.csv"));
  fs::remove_all(d);
}

// A full disk mid-movie left movie.mp4 unplayable (ffprobe found no frames).
TEST(HostileOutputs, AFullDiskKeepsTheMoviePlayable) {
  const fs::path d = test::fresh_dir("fullmovie");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, test::small_run(0.3, R"("frame_every": 0.02, "png": false,
                                               "mp4": {"fps": 10})",
                                        R"("render": {"width": 320, "height": 240})"));
  test::Limits lim;
  lim.file_size = 25000;  // the movie outgrows it after a few fragments
  auto o = outcome({"run", ctl.string(), "-o", run.string()}, d, lim);
  ASSERT_EQ(o.code, 5) << o.log;
  EXPECT_TRUE(contains(o.log, "movie.mp4")) << o.log;
  const auto probe = capflow::testing::ffprobe((run / "movie.mp4").string());
  EXPECT_TRUE(probe.ok) << probe.raw;
  EXPECT_GE(probe.packets, 1) << probe.raw;
  // room again: the resume finishes, every movie playable
  o = outcome({"run", "--resume", run.string()}, d);
  ASSERT_EQ(o.code, 0) << o.log;
  long frames = 0;
  for (const auto& e : fs::directory_iterator(run))
    if (e.path().extension() == ".mp4") {
      const auto p = capflow::testing::ffprobe(e.path().string());
      EXPECT_TRUE(p.ok) << e.path() << p.raw;
      frames += p.packets;
    }
  EXPECT_GE(frames, 16);  // t = 0, 0.02, ..., 0.3 (frames after the checkpoint made again)
  fs::remove_all(d);
}

// After a full disk the frames written before were lost across the resume: the checkpoint
// counted frames the renderer had not written (frames 0-2 never existed).
TEST(HostileOutputs, AFullDiskLeavesNoGapInTheFrames) {
  const fs::path d = test::fresh_dir("fullframes");
  const fs::path ctl = d / "c.json";
  for (long limit : {3000L, 6000L, 9000L}) {
    const fs::path run = d / ("run" + std::to_string(limit));
    test::write_file(ctl, test::small_run(0.3, R"("frame_every": 0.02, "mp4": false,
                                                 "checkpoint_every": 0.06)",
                                          R"("render": {"width": 96, "height": 64})"));
    test::Limits lim;
    lim.file_size = limit;  // frames, CSV rows or a checkpoint: whichever outgrows it first
    auto o = outcome({"run", ctl.string(), "-o", run.string()}, d, lim);
    ASSERT_EQ(o.code, 5) << o.log;
    if (!fs::exists(run)) continue;  // the start failed: nothing left to resume
    long n = 0;
    EXPECT_TRUE(frames_without_gap(run, &n)) << limit;
    o = outcome({"run", "--resume", run.string()}, d);
    ASSERT_EQ(o.code, 0) << o.log;
    EXPECT_TRUE(frames_without_gap(run, &n)) << limit;
    EXPECT_EQ(n, 16) << limit;
  }
  fs::remove_all(d);
}

// After kill -9, 1 try in 3 lost frame_000004.png: the checkpoint counted it, the renderer had
// not written it. Each kill here comes at another moment; the frames never have a gap.
TEST(HostileOutputs, KilledRunsResumeWithoutAGapInTheFrames) {
  const fs::path d = test::fresh_dir("killframes");
  const fs::path ctl = d / "c.json";
  test::write_file(ctl, test::small_run(0.3, R"("frame_every": 0.02, "checkpoint_every": 0.04,
                                               "mp4": false)",
                                        R"("render": {"width": 320, "height": 240})"));
  for (long rows : {3, 6, 9}) {
    const fs::path run = d / ("run" + std::to_string(rows));
    const pid_t pid = test::start_capflow({"run", ctl.string(), "-o", run.string()}, d / "log");
    ASSERT_TRUE(wait_rows(run, rows));
    kill(pid, SIGKILL);
    test::wait_exit(pid, 10);
    const auto o = outcome({"run", "--resume", run.string()}, d);
    ASSERT_EQ(o.code, 0) << o.log;
    long n = 0;
    EXPECT_TRUE(frames_without_gap(run, &n)) << rows;
    EXPECT_EQ(n, 16) << rows;
  }
  fs::remove_all(d);
}

// After SIGINT or SIGTERM mid-run with adaptive steps, half the resumes differed from the
// uninterrupted run in the tenth digit and in dt: the signal's checkpoint lacked the step-size
// controller's memory. Now every resume is bit for bit (all columns but wall_s).
TEST(HostileOutputs, ResumesAfterSignalsAreBitForBit) {
  const fs::path d = test::fresh_dir("signals");
  const fs::path ctl = d / "c.json";
  test::write_file(ctl, R"({"mesh": {"elements": 6, "nb": 8},
      "ca": [{"ca": 0.3, "hold": 0.3}, {"ramp": {"to": 0.5, "rate": 0.5}}],
      "time": {"t_end": 1.2}, "output": {"csv_every": 0.02, "checkpoint_every": 0.4}})");
  ASSERT_EQ(test::capflow({"run", ctl.string(), "-o", (d / "ref").string()}, d / "ref.log"), 0);
  const auto ref = test::rows_without_wall(d / "ref" / "timeseries.csv");
  int k = 0;
  for (const auto& [sig, rows] : std::vector<std::pair<int, long>>{
           {SIGTERM, 7}, {SIGINT, 13}, {SIGTERM, 22}, {SIGINT, 31}, {SIGTERM, 44}}) {
    const fs::path run = d / ("run" + std::to_string(k++));
    const pid_t pid = test::start_capflow({"run", ctl.string(), "-o", run.string()}, d / "log");
    ASSERT_TRUE(wait_rows(run, rows));
    kill(pid, sig);
    ASSERT_EQ(test::wait_exit(pid, 60), 0);
    ASSERT_EQ(test::capflow({"run", "--resume", run.string()}, d / "resume.log"), 0)
        << test::read_file(d / "resume.log");
    EXPECT_EQ(test::rows_without_wall(run / "timeseries.csv"), ref)
        << "signal " << sig << " after " << rows << " rows";
  }
  fs::remove_all(d);
}

// A torn last row of timeseries.csv (a kill mid-write) made --resume refuse. Resume now cuts the
// file back, keeps the torn bytes aside, and - when the torn row is one the newest checkpoint
// counts - continues from the checkpoint before: the result is that of the uninterrupted run.
TEST(HostileOutputs, ATornRowIsKeptAsideAndTheRunResumes) {
  const fs::path d = test::fresh_dir("torn");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, test::small_run(0.2, R"("checkpoint_every": 0.08)"));
  ASSERT_EQ(test::capflow({"run", ctl.string(), "-o", (d / "ref").string(), "--t-end", "0.3"},
                          d / "ref.log"),
            0);
  ASSERT_EQ(test::capflow({"run", ctl.string(), "-o", run.string()}, d / "a.log"), 0);
  const fs::path csv = run / "timeseries.csv";
  const auto size = fs::file_size(csv);
  fs::resize_file(csv, size - 9);  // the last row (t = 0.2, counted by the final checkpoint)
  const auto o = outcome({"run", "--resume", run.string(), "--t-end", "0.3"}, d);
  ASSERT_EQ(o.code, 0) << o.log;
  EXPECT_TRUE(fs::exists(run / "timeseries.csv.torn"));
  EXPECT_TRUE(contains(o.log, "skipped a checkpoint")) << o.log;
  EXPECT_EQ(test::rows_without_wall(csv), test::rows_without_wall(d / "ref" / "timeseries.csv"));
  fs::remove_all(d);
}

// capflow steady failed at Ca = 100 with exit 4 but kept no state; exit 4 promises the last
// good one.
TEST(HostileOutputs, AFailedSteadyKeepsItsLastGoodState) {
  const fs::path d = test::fresh_dir("steady100");
  test::write_file(d / "c.json", R"({"mesh": {"elements": 6, "nb": 6}, "ca": 100})");
  auto o = outcome({"steady", (d / "c.json").string(), "-o", (d / "run").string()}, d);
  ASSERT_EQ(o.code, 4) << o.log;
  EXPECT_TRUE(contains(o.log, "last good state")) << o.log;
  ASSERT_FALSE(fs::is_empty(d / "run" / "checkpoints"));
  o = outcome({"render", (d / "run").string(), "-o", (d / "last.png").string()}, d);
  EXPECT_EQ(o.code, 0) << o.log;
  fs::remove_all(d);
}

// figure on a CSV holding 1e308 exited 1 ("gnuplot failed"), outside the exit contract: what
// gnuplot cannot draw is left out and noted; with nothing left to draw the run is refused (2).
TEST(HostileOutputs, FiguresLeaveOutWhatGnuplotCannotDraw) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "gnuplot not found (scripts/setup installs gnuplot-nox)";
  const fs::path d = test::fresh_dir("figbig");
  const fs::path run = d / "run";
  test::write_file(d / "c.json", test::small_run(0.1));
  ASSERT_EQ(test::capflow({"run", (d / "c.json").string(), "-o", run.string()}, d / "a.log"), 0);
  std::vector<std::string> lines = test::lines_of(run / "timeseries.csv");
  const auto with = [&](const std::string& v, bool all) {
    std::string out = lines[0] + "\n";
    for (size_t i = 1; i < lines.size(); ++i) {
      std::string row = lines[i];
      if (all || i == 2) row = v + row.substr(row.find(','));  // t
      out += row + "\n";
    }
    return out;
  };
  test::write_file(run / "timeseries.csv", with("1e308", false));
  auto o = outcome({"figure", run.string(), "-o", (d / "f").string(), "--kinds", "timeseries"},
                   d);
  EXPECT_EQ(o.code, 0) << o.log;
  EXPECT_TRUE(contains(test::read_file(d / "f" / "figures.md"), "left out (gnuplot cannot"));
  test::write_file(run / "timeseries.csv", with("1e308", true));
  o = outcome({"figure", run.string(), "-o", (d / "g").string(), "--kinds", "timeseries"}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  fs::remove_all(d);
}

// Output failures exit 5 and name the file, for every command that writes.
TEST(HostileOutputs, OutputFailuresExitFiveNamingTheFile) {
  const fs::path d = test::fresh_dir("exit5");
  test::write_file(d / "c.json", test::small_run(0.1, R"("checkpoint_every": 0.02)"));
  ASSERT_EQ(test::capflow({"run", (d / "c.json").string(), "-o", (d / "run").string()},
                          d / "a.log"),
            0);
  test::Limits lim;
  lim.file_size = 2000;  // a checkpoint, a PNG, a figure's script: each larger than this
  auto o = outcome({"run", (d / "c.json").string(), "-o", (d / "r5").string()}, d, lim);
  EXPECT_EQ(o.code, 5) << o.log;
  EXPECT_TRUE(contains(o.log, "cannot write")) << o.log;
  o = outcome({"render", (d / "run").string(), "-o", (d / "x.png").string()}, d, lim);
  EXPECT_EQ(o.code, 5) << o.log;
  EXPECT_TRUE(contains(o.log, "x.png")) << o.log;
  lim.file_size = 300;  // figures.md and every script are larger
  o = outcome({"figure", (d / "run").string(), "-o", (d / "f").string(), "--no-gnuplot",
               "--kinds", "timeseries"},
              d, lim);
  EXPECT_EQ(o.code, 5) << o.log;
  EXPECT_TRUE(contains(o.log, "cannot write")) << o.log;
  lim.file_size = 2000;
  test::write_file(d / "s.json", R"({"mesh": {"elements": 6, "nb": 6}, "ca": 0.3})");
  o = outcome({"steady", (d / "s.json").string(), "-o", (d / "st").string()}, d, lim);
  EXPECT_EQ(o.code, 5) << o.log;
  lim.file_size = 100;  // the case control files are larger
  test::write_file(d / "sw.json", R"({"base": {"ca": 0.3, "mesh": {"elements": 6, "nb": 6},
      "time": {"t_end": 0.02}}, "vary": {"ca": [0.2, 0.3]}, "output": {"dir": ")" +
                                      (d / "sw").string() + R"("}})");
  o = outcome({"sweep", (d / "sw.json").string()}, d, lim);
  EXPECT_EQ(o.code, 5) << o.log;
  EXPECT_TRUE(contains(o.log, "case_000.json")) << o.log;
  fs::remove_all(d);
}
