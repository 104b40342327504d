// capflow under mpirun (app/worker_team.h): 1, 2 and 3 ranks give the same run and the same steady
// states (every column but the wall time); a live edit and a stop on rank 0 reach the run and end
// every rank; a run checkpointed with 2 ranks resumes with 3 and ends as the 1-rank run does.
// Needs a build with MPI (CAPFLOW_MPI) and mpirun (scripts/setup installs both).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/run_checkpoint.h"
#include "parallel/team.h"
#include "process_util.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace capflow;

namespace {

bool have_mpirun() {
  return parallel::built_with_mpi() && std::system("command -v mpirun > /dev/null 2>&1") == 0;
}

std::vector<std::string> mpirun(int np, const std::vector<std::string>& args) {
  std::vector<std::string> v = {"/usr/bin/env",
                                "mpirun",
                                "--oversubscribe",
                                "--allow-run-as-root",
                                "--mca",
                                "mpi_yield_when_idle",
                                "1",
                                "-np",
                                std::to_string(np),
                                "-x",
                                "OMP_NUM_THREADS=1",
                                CAPFLOW_EXE};
  v.insert(v.end(), args.begin(), args.end());
  return v;
}

// The lines of a CSV without the column `drop` (the wall time).
std::vector<std::string> without(const fs::path& csv, const std::string& drop) {
  std::vector<std::string> lines = test::lines_of(csv);
  if (lines.empty()) return lines;
  std::vector<std::string> head;
  {
    std::stringstream h(lines[0]);
    for (std::string c; std::getline(h, c, ',');) head.push_back(c);
  }
  size_t k = 0;
  while (k < head.size() && head[k] != drop) ++k;
  for (std::string& l : lines) {
    std::vector<std::string> f;
    std::stringstream row(l);
    for (std::string c; std::getline(row, c, ',');) f.push_back(c);
    std::string out;
    for (size_t i = 0; i < f.size(); ++i)
      if (i != k) out += f[i] + ",";
    l = out;
  }
  return lines;
}

const char* kRun = R"({"capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 6},
  "flow": {"type": "planar-extension"}, "ca": 0.45, "time": {"t_end": T},
  "output": {"png": false, "mp4": false, "csv_every": 0.01, "checkpoint_every": 0.05}})";

std::string run_control(const std::string& t_end) {
  std::string s = kRun;
  s.replace(s.find("T}"), 1, t_end);
  return s;
}

// `capflow COMMAND CONTROL -o DIR` on np ranks (its log beside DIR); the exit code.
int on_ranks(int np, const std::string& command, const fs::path& control, const fs::path& dir) {
  return test::run_capflow(mpirun(np, {command, control.string(), "-o", dir.string()}),
                           dir.string() + ".log", 300);
}

}  // namespace

TEST(Mpi, OneTwoAndThreeRanksGiveTheSameRunAndSteadyStates) {
  if (!have_mpirun()) GTEST_SKIP() << "no MPI build or no mpirun (scripts/setup installs them)";
  const fs::path d = test::fresh_dir("mpi_same");
  test::write_file(d / "run.json", run_control("0.2"));
  test::write_file(d / "steady.json",
                   R"({"capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 6,
    "division": "diagonal"}, "ca": [{"ca": 0.3}, {"steps": {"to": 0.4, "by": 0.1}}],
    "output": {"mp4": false}})");
  for (int np : {1, 2, 3}) {
    const std::string n = std::to_string(np);
    ASSERT_EQ(on_ranks(np, "run", d / "run.json", d / ("run" + n)), 0)
        << test::read_file(d / ("run" + n + ".log"));
    ASSERT_EQ(on_ranks(np, "steady", d / "steady.json", d / ("steady" + n)), 0)
        << test::read_file(d / ("steady" + n + ".log"));
  }
  const auto run1 = without(d / "run1" / "timeseries.csv", "wall_s");
  const auto steady1 = without(d / "steady1" / "steady.csv", "wall_s");
  EXPECT_GT(run1.size(), 20u);
  EXPECT_EQ(steady1.size(), 3u);
  for (const char* n : {"2", "3"}) {
    EXPECT_EQ(without(d / (std::string("run") + n) / "timeseries.csv", "wall_s"), run1) << n;
    EXPECT_EQ(without(d / (std::string("steady") + n) / "steady.csv", "wall_s"), steady1) << n;
  }
  fs::remove_all(d);
}

TEST(Mpi, AViscosityRatioRunIsTheSameOnOneTwoAndThreeRanks) {
  // lambda = 5: the double-layer matrix of every solve is assembled in row shares on the ranks
  // (app/worker_team.h); the run, its GMRES iterations and its checkpointed warm start are the
  // same bit for bit.
  if (!have_mpirun()) GTEST_SKIP() << "no MPI build or no mpirun (scripts/setup installs them)";
  const fs::path d = test::fresh_dir("mpi_lambda");
  std::string ctl = run_control("0.1");
  ctl.replace(ctl.find(R"("C": 1})"), 7, R"("C": 1, "viscosity_ratio": 5})");
  test::write_file(d / "run.json", ctl);
  for (int np : {1, 2, 3}) {
    const std::string n = std::to_string(np);
    ASSERT_EQ(on_ranks(np, "run", d / "run.json", d / ("run" + n)), 0)
        << test::read_file(d / ("run" + n + ".log"));
  }
  const auto run1 = without(d / "run1" / "timeseries.csv", "wall_s");
  EXPECT_GT(run1.size(), 10u);
  for (const char* n : {"2", "3"})
    EXPECT_EQ(without(d / (std::string("run") + n) / "timeseries.csv", "wall_s"), run1) << n;
  // the final states bit for bit: positions and the GMRES warm start
  const auto last = [&](const char* n) {
    return app::read_latest_checkpoint(d / (std::string("run") + n), nullptr);
  };
  const app::RunCheckpoint c1 = last("1");
  ASSERT_GT(c1.krylov_warm.size(), 0);
  for (const char* n : {"2", "3"}) {
    const app::RunCheckpoint c = last(n);
    EXPECT_EQ(c.t, c1.t) << n;
    EXPECT_TRUE(c.x == c1.x) << n;
    EXPECT_TRUE(c.krylov_warm == c1.krylov_warm) << n;
  }
  fs::remove_all(d);
}

TEST(Mpi, AnEditAndAStopOnRankZeroReachTheRunAndEndEveryRank) {
  if (!have_mpirun()) GTEST_SKIP() << "no MPI build or no mpirun (scripts/setup installs them)";
  const fs::path d = test::fresh_dir("mpi_stop");
  const fs::path ctl = d / "run.json", run = d / "run";
  test::write_file(ctl, run_control("1000"));
  const pid_t pid = test::spawn(mpirun(2, {"run", ctl.string(), "-o", run.string()}), d / "log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= 5; }, 120))
      << test::read_file(d / "log");
  std::string edited = run_control("1000");
  edited.replace(edited.find("\"ca\": 0.45"), 10, "\"ca\": 0.5");
  test::write_file(ctl, edited);
  ASSERT_TRUE(test::wait_for([&] { return test::count_events(run, "edit") >= 1; }, 60))
      << test::read_file(d / "log");
  edited.replace(edited.find("\"output\""), 8, "\"run\": {\"state\": \"stopped\"}, \"output\"");
  test::write_file(ctl, edited);
  EXPECT_EQ(test::wait_exit(pid, 120), 0) << test::read_file(d / "log");
  const std::string events = test::read_file(run / "events.jsonl");
  EXPECT_NE(events.find("\"reason\":\"run.state is \\\"stopped\\\"\""), std::string::npos)
      << events;
  EXPECT_NE(events.find("\"accepted\":true"), std::string::npos) << events;
  fs::remove_all(d);
}

TEST(Mpi, ACheckpointOfTwoRanksResumesWithThree) {
  if (!have_mpirun()) GTEST_SKIP() << "no MPI build or no mpirun (scripts/setup installs them)";
  const fs::path d = test::fresh_dir("mpi_resume");
  test::write_file(d / "short.json", run_control("0.1"));
  test::write_file(d / "long.json", run_control("0.2"));
  ASSERT_EQ(test::run_capflow(
                mpirun(1, {"run", (d / "long.json").string(), "-o", (d / "whole").string()}),
                d / "log1", 300),
            0);
  ASSERT_EQ(test::run_capflow(
                mpirun(2, {"run", (d / "short.json").string(), "-o", (d / "split").string()}),
                d / "log2", 300),
            0);
  ASSERT_EQ(
      test::run_capflow(mpirun(3, {"run", "--resume", (d / "split").string(), "--t-end", "0.2"}),
                        d / "log3", 300),
      0)
      << test::read_file(d / "log3");
  EXPECT_EQ(without(d / "split" / "timeseries.csv", "wall_s"),
            without(d / "whole" / "timeseries.csv", "wall_s"));
  fs::remove_all(d);
}

TEST(Mpi, ASweepRunsEachCaseOnAGroupOfRanks) {
  // mpirun -np 4 capflow sweep --ranks-per-case 2: two groups of two ranks, each running its
  // cases (index % 2 == group) on both of its ranks; every case as a one-process sweep makes it,
  // bit for bit; run again it does nothing; 3 ranks cannot form groups of 2 (exit 2).
  if (!have_mpirun()) GTEST_SKIP() << "no MPI build or no mpirun (scripts/setup installs them)";
  const fs::path d = test::fresh_dir("mpi_sweep");
  const std::string sweep = R"({"base": {"capsule": {"law": "skalak", "C": 1},
    "mesh": {"elements": 6, "nb": 6}, "flow": {"type": "planar-extension"}, "ca": 0.3,
    "time": {"t_end": 0.1}, "output": {"png": false, "mp4": false, "csv_every": 0.01}},
    "vary": {"ca": [0.3, 0.45], "capsule.C": [1, 3]}, "output": {"dir": "DIR"}})";
  const auto sweep_file = [&](const std::string& name) {
    std::string s = sweep;
    s.replace(s.find("DIR"), 3, (d / name).string());
    test::write_file(d / (name + ".json"), s);
    return (d / (name + ".json")).string();
  };
  const std::string plain = sweep_file("plain"), grouped = sweep_file("grouped");
  // the sweep's report is on stdout: into the log with stderr
  const auto both = [](std::vector<std::string> args) {
    args.insert(args.begin(), {"/bin/sh", "-c", "exec \"$@\" 1>&2", "sh"});
    return args;
  };
  ASSERT_EQ(test::run_capflow({CAPFLOW_EXE, "sweep", plain}, d / "log_plain", 300), 0)
      << test::read_file(d / "log_plain");
  ASSERT_EQ(test::run_capflow(both(mpirun(4, {"sweep", grouped, "--ranks-per-case", "2"})),
                              d / "log_grouped", 300),
            0)
      << test::read_file(d / "log_grouped");
  for (const char* c : {"case_000", "case_001", "case_002", "case_003"}) {
    SCOPED_TRACE(c);
    const auto one = without(d / "plain" / c / "timeseries.csv", "wall_s");
    EXPECT_GT(one.size(), 5u);
    EXPECT_EQ(without(d / "grouped" / c / "timeseries.csv", "wall_s"), one);
    EXPECT_NE(test::read_file(d / "grouped" / (std::string(c) + ".log")).find("x 2 MPI ranks"),
              std::string::npos);
  }
  const std::string log = test::read_file(d / "log_grouped");
  EXPECT_NE(log.find("sweep [group 0/2]: case_000"), std::string::npos) << log;
  EXPECT_NE(log.find("sweep [group 1/2]: case_001"), std::string::npos) << log;
  const std::string summary = test::read_file(d / "grouped" / "sweep.csv");
  EXPECT_EQ(test::csv_rows(d / "grouped" / "sweep.csv"), 4);
  EXPECT_EQ(summary.find(",new,"), std::string::npos) << summary;

  ASSERT_EQ(test::run_capflow(both(mpirun(4, {"sweep", grouped, "--ranks-per-case", "2"})),
                              d / "log_again", 300),
            0)
      << test::read_file(d / "log_again");
  const std::string again = test::read_file(d / "log_again");
  EXPECT_EQ(again.find("running"), std::string::npos) << again;
  EXPECT_NE(again.find("done before, skipped"), std::string::npos) << again;
  EXPECT_EQ(test::read_file(d / "grouped" / "sweep.csv"), summary);

  EXPECT_EQ(test::run_capflow(mpirun(3, {"sweep", grouped, "--ranks-per-case", "2"}),
                              d / "log_three", 300),
            2);
  EXPECT_NE(test::read_file(d / "log_three").find("a multiple of 2"), std::string::npos);
  fs::remove_all(d);
}

namespace {

// The inodes of the TCP sockets in LISTEN state (/proc/net/tcp and tcp6, state 0A).
std::set<std::string> listening_inodes() {
  std::set<std::string> out;
  for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    const std::vector<std::string> lines = test::lines_of(table);
    for (size_t i = 1; i < lines.size(); ++i) {
      std::stringstream s(lines[i]);
      std::vector<std::string> f;
      for (std::string w; s >> w;) f.push_back(w);
      if (f.size() > 9 && f[3] == "0A") out.insert(f[9]);
    }
  }
  return out;
}

// The socket inodes a process holds.
std::set<std::string> socket_inodes(pid_t pid) {
  std::set<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
    const std::string link = fs::read_symlink(e.path(), ec).string();
    if (link.rfind("socket:[", 0) == 0) out.insert(link.substr(8, link.size() - 9));
  }
  return out;
}

// The capflow processes whose command line names `dir`.
std::vector<pid_t> capflow_ranks(const fs::path& dir) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmd = test::read_file(e.path() / "cmdline");
    std::replace(cmd.begin(), cmd.end(), '\0', ' ');
    if (cmd.rfind(CAPFLOW_EXE, 0) == 0 && cmd.find(dir.string()) != std::string::npos)
      out.push_back(static_cast<pid_t>(std::stol(name)));
  }
  return out;
}

}  // namespace

// Under mpirun the ranks listened on TCP on every interface (Open MPI's tcp transport). A job
// whose ranks all run on one node uses shared memory only: its ranks hold no listening socket.
TEST(Mpi, TheRanksOfASingleNodeJobOpenNoTcpListener) {
  if (!have_mpirun()) GTEST_SKIP() << "no MPI build or no mpirun (scripts/setup installs them)";
  const fs::path d = test::fresh_dir("mpi_tcp");
  const fs::path ctl = d / "run.json", run = d / "run";
  test::write_file(ctl, run_control("1000"));
  const pid_t pid = test::spawn(mpirun(2, {"run", ctl.string(), "-o", run.string()}), d / "log");
  ASSERT_TRUE(test::wait_for([&] { return test::csv_rows(run / "timeseries.csv") >= 3; }, 120))
      << test::read_file(d / "log");
  const std::vector<pid_t> ranks = capflow_ranks(run);
  EXPECT_EQ(ranks.size(), 2u);
  const std::set<std::string> listening = listening_inodes();
  for (pid_t r : ranks)
    for (const std::string& inode : socket_inodes(r))
      EXPECT_EQ(listening.count(inode), 0u) << "rank process " << r << " listens on TCP";
  std::string stop = run_control("1000");
  stop.replace(stop.find("\"output\""), 8, "\"run\": {\"state\": \"stopped\"}, \"output\"");
  test::write_file(ctl, stop);
  EXPECT_EQ(test::wait_exit(pid, 120), 0) << test::read_file(d / "log");
  fs::remove_all(d);
}
