// capflow sweep (app/sweep.h) through the executable: a 2 x 2 sweep (two cases side by side)
// finishes and a second call does nothing; a stopped sweep resumes its interrupted case; a changed
// sweep, a bad sweep file and a bad --case are refused with exit 2; --slurm writes a job array and
// --case runs one case.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <string>

#include "process_util.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace capflow;

namespace {

// A short Skalak run (t_end as given) and a sweep over ca x capsule.C into <d>/out.
fs::path write_sweep(const fs::path& d, double t_end, const std::string& vary) {
  test::write_file(d / "base.json",
                   R"({"capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 6},
    "flow": {"type": "planar-extension"}, "time": {"t_end": )" +
                       std::to_string(t_end) + R"(},
    "output": {"png": false, "mp4": false, "checkpoint_every": 0.5}})");
  test::write_file(d / "sweep.json", R"({"base": "base.json", "vary": )" + vary +
                                         R"(, "output": {"dir": ")" + (d / "out").string() +
                                         "\"}}");
  return d / "sweep.json";
}

int sweep(const std::vector<std::string>& extra, const fs::path& log) {
  std::vector<std::string> args = {CAPFLOW_EXE, "sweep"};
  args.insert(args.end(), extra.begin(), extra.end());
  return test::run_capflow(args, log, 300);
}

}  // namespace

TEST(Sweep, TwoByTwoFinishesAndASecondCallDoesNothing) {
  const fs::path d = test::fresh_dir("sweep_2x2");
  const fs::path s = write_sweep(d, 0.05, R"({"ca": [0.3, 0.6], "capsule.C": [1, 3]})");
  // two cases side by side
  ASSERT_EQ(sweep({s.string(), "--jobs", "2"}, d / "log1"), 0) << test::read_file(d / "log1");
  const std::vector<std::string> rows = test::lines_of(d / "out" / "sweep.csv");
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0], "case,ca,capsule.C,status,exit_code,reason,t,D,L,S,W,steps,dir");
  for (int i = 1; i <= 4; ++i)
    EXPECT_NE(rows[i].find(",done,0,t_end reached,0.05,"), std::string::npos) << rows[i];
  EXPECT_EQ(rows[4].substr(0, 10), "3,0.6,3,do");
  // the case's run used its values
  EXPECT_NE(test::read_file(d / "out" / "case_003" / "control.json").find("\"C\": 3"),
            std::string::npos);
  // again: every case is done, nothing runs (no second end event anywhere)
  ASSERT_EQ(sweep({s.string()}, d / "log2"), 0) << test::read_file(d / "log2");
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(test::count_events(d / "out" / ("case_00" + std::to_string(i)), "end"), 1) << i;
  // capflow figure takes the sweep directory for its cases, labelled by their values
  ASSERT_EQ(test::run_capflow({CAPFLOW_EXE, "figure", (d / "out").string(), "-o",
                               (d / "fig").string(), "--kinds", "timeseries", "--no-gnuplot"},
                              d / "log_fig", 120),
            0)
      << test::read_file(d / "log_fig");
  EXPECT_NE(test::read_file(d / "fig" / "figures.md").find("(ca=0.6 capsule.C=3)"),
            std::string::npos)
      << test::read_file(d / "fig" / "figures.md");
  // a changed sweep into the same directory is refused: its runs would not belong to it
  write_sweep(d, 0.05, R"({"ca": [0.3, 0.5], "capsule.C": [1, 3]})");
  EXPECT_EQ(sweep({s.string()}, d / "log3"), 2);
  EXPECT_NE(test::read_file(d / "log3").find("differs from case_002"), std::string::npos)
      << test::read_file(d / "log3");
  fs::remove_all(d);
}

TEST(Sweep, AStoppedSweepResumesItsInterruptedCase) {
  const fs::path d = test::fresh_dir("sweep_stop");
  const fs::path s = write_sweep(d, 6.0, R"({"ca": [0.3, 0.45]})");
  const pid_t pid = test::spawn({CAPFLOW_EXE, "sweep", s.string()}, d / "log1");
  const fs::path c0 = d / "out" / "case_000";
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(c0, "checkpoint") >= 2; }, 120))
      << test::read_file(d / "log1");
  kill(pid, SIGTERM);
  ASSERT_EQ(test::wait_exit(pid, 120), 0) << test::read_file(d / "log1");
  const std::vector<std::string> rows = test::lines_of(d / "out" / "sweep.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_NE(rows[1].find(",interrupted,0,stopped by signal,"), std::string::npos) << rows[1];
  EXPECT_NE(rows[2].find(",new,"), std::string::npos) << rows[2];
  EXPECT_FALSE(fs::exists(d / "out" / "case_001")) << "no case starts after the stop";
  // again: case 0 resumes from its checkpoint, case 1 starts
  ASSERT_EQ(sweep({s.string()}, d / "log2"), 0) << test::read_file(d / "log2");
  EXPECT_EQ(test::count_events(c0, "end"), 2);
  EXPECT_EQ(test::count_events(c0, "resume"), 1);
  for (const std::string& row : test::lines_of(d / "out" / "sweep.csv"))
    if (row[0] != 'c') {
      EXPECT_NE(row.find(",done,0,t_end reached,6,"), std::string::npos) << row;
    }
  fs::remove_all(d);
}

TEST(Sweep, SlurmWritesAJobArrayAndACaseRunsAlone) {
  const fs::path d = test::fresh_dir("sweep_slurm");
  const fs::path s = write_sweep(d, 0.05, R"({"ca": [0.3, 0.6]})");
  ASSERT_EQ(sweep({s.string(), "--slurm"}, d / "log1"), 0) << test::read_file(d / "log1");
  const std::string batch = test::read_file(d / "out" / "sweep.sbatch");
  EXPECT_NE(batch.find("#SBATCH --array=0-1"), std::string::npos) << batch;
  EXPECT_NE(batch.find("--case \"$SLURM_ARRAY_TASK_ID\""), std::string::npos) << batch;
  EXPECT_FALSE(fs::exists(d / "out" / "case_000")) << "--slurm runs nothing";
  ASSERT_EQ(sweep({s.string(), "--case", "1"}, d / "log2"), 0) << test::read_file(d / "log2");
  EXPECT_FALSE(fs::exists(d / "out" / "case_000"));
  EXPECT_EQ(test::count_events(d / "out" / "case_001", "end"), 1);
  ASSERT_EQ(sweep({s.string(), "--summary"}, d / "log3"), 0);
  const std::vector<std::string> rows = test::lines_of(d / "out" / "sweep.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_NE(rows[1].find(",new,"), std::string::npos);
  EXPECT_NE(rows[2].find(",done,"), std::string::npos);
  EXPECT_EQ(sweep({s.string(), "--case", "2"}, d / "log4"), 2);
  EXPECT_NE(test::read_file(d / "log4").find("--case 2: the sweep has cases 0 to 1"),
            std::string::npos);
  fs::remove_all(d);
}

TEST(Sweep, ABadSweepFileExitsTwoNamingTheField) {
  const fs::path d = test::fresh_dir("sweep_bad");
  write_sweep(d, 0.05, R"({"ca": [0.3, 200]})");
  EXPECT_EQ(sweep({(d / "sweep.json").string()}, d / "log"), 2);
  EXPECT_NE(test::read_file(d / "log").find("case 1 (ca = 200): ca: value 200 is out of range"),
            std::string::npos)
      << test::read_file(d / "log");
  EXPECT_FALSE(fs::exists(d / "out")) << "nothing is made for a bad sweep";
  fs::remove_all(d);
}

TEST(Sweep, TheRanksOfAnMpiLauncherShareTheCases) {
  // mpirun -np 2: each rank runs the cases with index % 2 == its rank, once each; the summary
  // (written under a lock after each case) ends complete. scripts/setup installs openmpi-bin.
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "mpirun not found (scripts/setup installs openmpi-bin)";
  const fs::path d = test::fresh_dir("sweep_mpi");
  const fs::path s = write_sweep(d, 0.05, R"({"ca": [0.3, 0.45, 0.6], "capsule.C": [1, 3]})");
  ASSERT_EQ(
      test::run_capflow({"/usr/bin/env", "mpirun", "--oversubscribe", "--allow-run-as-root", "-np",
                         "2", "-x", "OMP_NUM_THREADS=1", CAPFLOW_EXE, "sweep", s.string()},
                        d / "log", 300),
      0)
      << test::read_file(d / "log");
  const std::vector<std::string> rows = test::lines_of(d / "out" / "sweep.csv");
  ASSERT_EQ(rows.size(), 7u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NE(rows[i + 1].find(",done,0,t_end reached,"), std::string::npos) << rows[i + 1];
    EXPECT_EQ(test::count_events(d / "out" / ("case_00" + std::to_string(i)), "end"), 1) << i;
  }
  fs::remove_all(d);
}
