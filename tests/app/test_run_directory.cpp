// The run directory and the exit codes (Milestone 7), through the capflow executable:
//  * one process per run directory (a second run, --overwrite or --resume is refused naming the
//    holder's PID), no run onto an existing run without --overwrite, never into a non-empty
//    directory that is not a run ("/");
//  * --overwrite removes the old run's files, so a later resume cannot pick its checkpoints;
//  * a full disk (RLIMIT_FSIZE) stops the run with exit 5 naming the file, no half row and no
//    temporary checkpoint, and --resume then continues with consistent files;
//  * after --resume, PNG frames continue the numbering and the movie goes to movie.part2.mp4;
//  * every user error exits 2 (bad control input, start.from, output directory), never 3.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "output/records.h"
#include "process_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {

std::string small(double t_end, const std::string& extra = "",
                  const std::string& output = R"({"csv_every": 0.004})") {
  std::ostringstream s;
  s << R"({"mesh": {"elements": 6, "nb": 6}, "time": {"dt": 0.004, "t_end": )" << t_end
    << R"(}, "ca": 0.3, "output": )" << output << R"(, "numerics": {"threads": 1})" << extra << "}";
  return s.str();
}

int capflow_run(const std::vector<std::string>& args, const fs::path& log, long fsize = -1) {
  std::vector<std::string> a = {CAPFLOW_EXE};
  a.insert(a.end(), args.begin(), args.end());
  return test::run_capflow(a, log, 120, fsize);
}

// Every data row of timeseries.csv is whole (the layout's fields); t strictly increases.
void expect_consistent_timeseries(const fs::path& csv) {
  const std::string text = test::read_file(csv);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << "the last row is cut";
  double last_t = -1;
  const std::vector<std::string> lines = test::lines_of(csv);
  for (size_t i = 1; i < lines.size(); ++i) {
    EXPECT_EQ(std::count(lines[i].begin(), lines[i].end(), ','),
              static_cast<long>(output::records::timeseries().columns.size()) - 1)
        << "row " << i << ": " << lines[i];
    const double t = std::stod(lines[i]);
    EXPECT_GT(t, last_t) << "row " << i;
    last_t = t;
  }
}

std::vector<std::string> checkpoint_names(const fs::path& run) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(run / "checkpoints"))
    out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(RunDirectory, OneProcessPerRunDirectory) {
  const fs::path d = test::fresh_dir("lock");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, small(1000));
  const pid_t pid =
      test::spawn({CAPFLOW_EXE, "run", ctl.string(), "-o", run.string()}, d / "first.log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= 5; }, 60));
  EXPECT_EQ(capflow_run({"run", ctl.string(), "-o", run.string()}, d / "second.log"), 2);
  EXPECT_NE(test::read_file(d / "second.log").find("already holds a capflow run"),
            std::string::npos)
      << test::read_file(d / "second.log");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"run", ctl.string(), "-o", run.string(), "--overwrite"},
        std::vector<std::string>{"run", "--resume", run.string()}}) {
    EXPECT_EQ(capflow_run(args, d / "other.log"), 2) << args.back();
    const std::string log = test::read_file(d / "other.log");
    EXPECT_NE(log.find("in use by another capflow process (PID " + std::to_string(pid) + ")"),
              std::string::npos)
        << log;
  }
  kill(pid, SIGINT);
  EXPECT_EQ(test::wait_exit(pid, 30), 0) << test::read_file(d / "first.log");
  expect_consistent_timeseries(run / "timeseries.csv");
  EXPECT_EQ(test::count_events(run, "start"), 1);
  EXPECT_EQ(test::count_events(run, "end"), 1);
  fs::remove_all(d);
}

TEST(RunDirectory, OverwriteReplacesTheOldRunAndForeignDirectoriesAreRefused) {
  const fs::path d = test::fresh_dir("overwrite");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, small(0.04));
  ASSERT_EQ(capflow_run({"run", ctl.string(), "-o", run.string()}, d / "a.log"), 0);
  EXPECT_EQ(checkpoint_names(run),
            (std::vector<std::string>{"ckpt_0000000000.ckpt", "ckpt_0000000010.ckpt"}));
  test::write_file(run / "notes.txt", "mine");
  test::write_file(ctl, small(0.02));
  EXPECT_EQ(capflow_run({"run", ctl.string(), "-o", run.string()}, d / "b.log"), 2);
  EXPECT_EQ(test::csv_rows(run / "timeseries.csv"), 11);  // untouched
  EXPECT_EQ(capflow_run({"run", ctl.string(), "-o", run.string(), "--overwrite"}, d / "c.log"), 0)
      << test::read_file(d / "c.log");
  // the old run's checkpoint at step 10 is gone: a resume cannot pick it up
  EXPECT_EQ(checkpoint_names(run),
            (std::vector<std::string>{"ckpt_0000000000.ckpt", "ckpt_0000000005.ckpt"}));
  EXPECT_EQ(test::csv_rows(run / "timeseries.csv"), 6);
  EXPECT_EQ(test::read_file(run / "notes.txt"), "mine");  // not a run file: kept
  // Not a capflow run and not empty: refused, --overwrite or not ("/" among them).
  const fs::path foreign = d / "foreign";
  fs::create_directories(foreign);
  test::write_file(foreign / "data.txt", "x");
  for (const fs::path& target : {foreign, fs::path("/")}) {
    for (bool overwrite : {false, true}) {
      std::vector<std::string> args = {"run", ctl.string(), "-o", target.string()};
      if (overwrite) args.push_back("--overwrite");
      EXPECT_EQ(capflow_run(args, d / "f.log"), 2) << target;
      EXPECT_NE(test::read_file(d / "f.log").find("is not empty and is not a capflow run"),
                std::string::npos)
          << test::read_file(d / "f.log");
    }
  }
  EXPECT_FALSE(fs::exists("/run.lock"));
  EXPECT_FALSE(fs::exists("/timeseries.csv"));
  EXPECT_FALSE(fs::exists(foreign / "run.lock"));
  // A file where the run directory should be.
  EXPECT_EQ(capflow_run({"run", ctl.string(), "-o", (foreign / "data.txt").string()}, d / "g.log"),
            2);
  fs::remove_all(d);
}

TEST(RunDirectory, FullDiskStopsWithExitFiveAndResumeContinuesConsistently) {
  const fs::path d = test::fresh_dir("diskfull");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, small(2.0));
  // Files may grow to 40 kB: the checkpoints (~15 kB) fit, timeseries.csv outgrows it.
  EXPECT_EQ(capflow_run({"run", ctl.string(), "-o", run.string()}, d / "a.log", 40000), 5)
      << test::read_file(d / "a.log");
  const std::string log = test::read_file(d / "a.log");
  EXPECT_NE(log.find("cannot write " + (run / "timeseries.csv").string()), std::string::npos)
      << log;
  EXPECT_NE(log.find("resume with: capflow run --resume"), std::string::npos) << log;
  expect_consistent_timeseries(run / "timeseries.csv");
  for (const std::string& name : checkpoint_names(run))
    EXPECT_EQ(fs::path(name).extension(), ".ckpt") << name;
  bool end_event = false;
  for (const auto& e : test::events(run))
    if (e["event"] == "end") end_event = e["exit_code"] == 5;
  EXPECT_TRUE(end_event);
  // Once the disk has room again the run resumes and completes with consistent files.
  EXPECT_EQ(capflow_run({"run", "--resume", run.string()}, d / "b.log"), 0)
      << test::read_file(d / "b.log");
  expect_consistent_timeseries(run / "timeseries.csv");
  EXPECT_EQ(test::csv_rows(run / "timeseries.csv"), 501);  // t = 0, 0.004, ..., 2
  fs::remove_all(d);
}

TEST(RunDirectory, FailedCheckpointWriteIsAnOutputFailure) {
  const fs::path d = test::fresh_dir("ckptfail");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, small(0.04));
  // 8 kB: the CSV header and rows fit, no checkpoint does.
  EXPECT_EQ(capflow_run({"run", ctl.string(), "-o", run.string()}, d / "a.log", 8000), 5);
  const std::string log = test::read_file(d / "a.log");
  EXPECT_NE(log.find("cannot write " + (run / "checkpoints" / "ckpt_0000000000.ckpt").string()),
            std::string::npos)
      << log;
  // A start that never wrote a checkpoint leaves nothing behind: the same command works once
  // there is room again.
  EXPECT_NE(log.find("the run could not start"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(run)) << "the run directory it made is removed";
  EXPECT_EQ(capflow_run({"run", ctl.string(), "-o", run.string()}, d / "b.log"), 0)
      << test::read_file(d / "b.log");
  fs::remove_all(d);
}

TEST(RunDirectory, ResumedFramesContinueTheNumbering) {
  const fs::path d = test::fresh_dir("frames");
  const fs::path ctl = d / "c.json", run = d / "run";
  test::write_file(ctl, small(0.04, R"(, "render": {"width": 64, "height": 48, "msaa": 0})",
                              R"({"csv_every": 0.004, "frame_every": 0.008, "mp4": {"fps": 10}})"));
  ASSERT_EQ(capflow_run({"run", ctl.string(), "-o", run.string()}, d / "a.log"), 0)
      << test::read_file(d / "a.log");
  std::set<std::string> first;
  for (const auto& e : fs::directory_iterator(run / "frames"))
    first.insert(e.path().filename().string());
  ASSERT_EQ(first.size(), 6u);  // t = 0, 0.008, ..., 0.04
  const std::string frame0 = test::read_file(run / "frames" / "frame_000000.png");
  const auto mtime5 = fs::last_write_time(run / "frames" / "frame_000005.png");
  ASSERT_EQ(capflow_run({"run", "--resume", run.string(), "--t-end", "0.08"}, d / "b.log"), 0)
      << test::read_file(d / "b.log");
  std::set<std::string> all;
  for (const auto& e : fs::directory_iterator(run / "frames"))
    all.insert(e.path().filename().string());
  EXPECT_EQ(all.size(), 11u);
  EXPECT_TRUE(all.count("frame_000010.png"));
  EXPECT_EQ(test::read_file(run / "frames" / "frame_000000.png"), frame0);
  EXPECT_EQ(fs::last_write_time(run / "frames" / "frame_000005.png"), mtime5);  // not rewritten
  EXPECT_TRUE(fs::exists(run / "movie.mp4"));
  EXPECT_TRUE(fs::exists(run / "movie.part2.mp4"));
  EXPECT_EQ(test::count_events(run, "resume"), 1);
  fs::remove_all(d);
}

TEST(ExitCodes, UserErrorsExitTwoAndNameTheProblem) {
  const fs::path d = test::fresh_dir("exit2");
  struct Case {
    std::string name, text, expect;
  };
  const std::string deep =
      "{\"ca\": 0.3, \"mesh\": " + std::string(70000, '[') + std::string(70000, ']') + "}";
  const std::vector<Case> cases = {
      {"deep", deep, "nested deeper"},
      {"overflow",
       small(0.04).substr(0, small(0.04).size() - 1) + R"(, "steady": {"window": 1e400}})",
       "steady.window: number 1e400 is outside the range of a double"},
      {"duplicate", R"({"ca": 0.3, "time": {"dt": 0.004}, "time": {"t_end": 1}})",
       "key \"time\" is given twice"},
      {"tiny_dt", R"({"ca": 0.3, "time": {"dt": 1e-300}})",
       "time.dt: value 1e-300 is out of range"},
      {"short", R"({"ca": 0.3, "time": {"dt": 0.01, "t_end": 0.001}})",
       "not one step would be taken"},
      {"ramp_from_rest", R"({"ca": [{"ramp": {"to": 1, "rate": 0.1}}]})",
       "a run from rest has none"},
      {"start_from", R"({"ca": 0.3, "start": {"from": "/nonexistent/run"}})",
       "start.from: /nonexistent/run: no such"},
  };
  for (const Case& c : cases) {
    const fs::path f = d / (c.name + ".json");
    test::write_file(f, c.text);
    EXPECT_EQ(capflow_run({"run", f.string(), "-o", (d / ("run_" + c.name)).string()}, d / "e.log"),
              2)
        << c.name;
    const std::string log = test::read_file(d / "e.log");
    EXPECT_NE(log.find(c.expect), std::string::npos) << c.name << ": " << log;
    EXPECT_EQ(log.find("internal error"), std::string::npos) << c.name;
    EXPECT_FALSE(fs::exists(d / ("run_" + c.name)))
        << c.name << ": a refused run must not create its directory";
  }
  // A FIFO as control file is refused at once (not a blocked reader).
  ASSERT_EQ(::mkfifo((d / "fifo.json").c_str(), 0644), 0);
  EXPECT_EQ(capflow_run({"run", (d / "fifo.json").string(), "-o", (d / "r").string()}, d / "e.log"),
            2);
  EXPECT_NE(test::read_file(d / "e.log").find("is a FIFO"), std::string::npos);
  // --resume of something that is not a run, --t-end before the run's time.
  EXPECT_EQ(capflow_run({"run", "--resume", d.string()}, d / "e.log"), 2);
  test::write_file(d / "ok.json", small(0.02));
  ASSERT_EQ(capflow_run({"run", (d / "ok.json").string(), "-o", (d / "ok").string()}, d / "e.log"),
            0);
  EXPECT_EQ(capflow_run({"run", "--resume", (d / "ok").string()}, d / "e.log"),
            2);  // at t_end already
  EXPECT_NE(test::read_file(d / "e.log").find("give --t-end to run on"), std::string::npos)
      << test::read_file(d / "e.log");
  EXPECT_EQ(capflow_run({"run", "--resume", (d / "ok").string(), "--t-end", "0.01"}, d / "e.log"),
            2);
  EXPECT_EQ(capflow_run({"run", "--resume", (d / "ok").string(), "--t-end", "0.03"}, d / "e.log"),
            0);
  fs::remove_all(d);
}
