#include "app/sweep.h"

#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <vector>

#include "app/child_process.h"
#include "app/console.h"
#include "app/errors.h"
#include "app/run_command.h"
#include "app/stop_signal.h"
#include "app/sweep_directory.h"
#include "app/worker_team.h"
#include "control/sweep.h"
#include "parallel/team.h"

namespace capflow::app {

namespace fs = std::filesystem;

namespace {

// What continues case c: resume an interrupted run that has a checkpoint, else start it afresh.
RunArgs case_run_args(const control::SweepPlan& plan, const control::SweepCase& c,
                      const CaseState& state) {
  const fs::path run = fs::path(plan.dir) / c.name;
  RunArgs r;
  if (state.status == CaseStatus::Interrupted && state.has_checkpoint) {
    r.resume = run.string();
  } else {
    r.control = (fs::path(plan.dir) / (c.name + ".json")).string();
    r.output_dir = run.string();
    r.overwrite = true;
  }
  return r;
}

// The same as the command line of a `capflow run` child process.
std::vector<std::string> run_command_line(const std::string& exe, const RunArgs& r) {
  if (!r.resume.empty()) return {exe, "run", "--resume", r.resume};
  std::vector<std::string> v{exe, "run", r.control, "-o", r.output_dir};
  if (r.overwrite) v.push_back("--overwrite");
  return v;
}

// --ranks-per-case G: the launcher's ranks in groups of G (parallel::split). Throws UserError
// (on every rank alike) unless MPI was started with a multiple of G ranks.
void form_groups(const SweepArgs& a) {
  const int g = a.ranks_per_case;
  check_sweep_args(a, 1);
  if (!parallel::built_with_mpi())
    throw UserError("--ranks-per-case " + std::to_string(g) +
                    ": this capflow was built without MPI (install libopenmpi-dev and rebuild)");
  parallel::start(nullptr, nullptr);
  if (parallel::size() < g || !parallel::split(g)) {
    const int n = parallel::size();
    parallel::finish();  // every rank refuses alike: nobody is left to serve or be served
    throw UserError("--ranks-per-case " + std::to_string(g) + ": needs mpirun -np N with N a " +
                    "multiple of " + std::to_string(g) + " (this sweep has " + std::to_string(n) +
                    " rank" + (n == 1 ? "" : "s") + ")");
  }
}

}  // namespace

int run_sweep(const SweepArgs& a) {
  if (a.ranks_per_case > 1) {
    form_groups(a);
    // the group's other ranks share the velocity evaluations of its cases until it ends
    if (parallel::rank() > 0) return serve_team();
  }
  const control::SweepPlan plan = control::load_sweep_file(a.file);  // exit 2 when bad
  const int n = static_cast<int>(plan.cases.size());
  if (a.only_case >= n)
    throw UserError("--case " + std::to_string(a.only_case) + ": the sweep has cases 0 to " +
                    std::to_string(n - 1));
  check_sweep_args(a, launcher_share().size);
  if (a.only_case < 0 && !a.summary) prepare_sweep_directory(plan, a.overwrite);
  write_case_files(plan);
  if (a.slurm) {
    write_slurm(plan, a.file, self_exe());
    console::out("sweep: " + std::to_string(n) + " cases; submit " +
                 (fs::path(plan.dir) / "sweep.sbatch").string() +
                 " with sbatch, then run capflow sweep " + a.file + " --summary");
    return exit_code::kOk;
  }
  KnownStates known;
  if (a.summary) {
    write_summary(plan, &known);
    return exit_code::kOk;
  }
  const std::atomic<bool>* stop = install_stop_signals();
  const std::string exe = self_exe();
  // --jobs N: N cases side by side, the cores divided among them (unless OMP_NUM_THREADS is set)
  const int jobs = std::max(1, a.jobs);
  const int threads =
      jobs > 1 && !std::getenv("OMP_NUM_THREADS")
          ? std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / jobs)
          : 0;
  struct Running {
    pid_t pid;
    const control::SweepCase* c;
    std::chrono::steady_clock::time_point t0;
  };
  std::vector<Running> running;
  int failed = 0, output_failed = 0;
  bool forwarded = false;
  const bool groups = a.ranks_per_case > 1;
  const Share share = a.only_case >= 0 ? Share{}
                      : groups         ? Share{parallel::group(), parallel::groups()}
                                       : launcher_share();
  const std::string who = share.size > 1 ? "sweep [" + std::string(groups ? "group " : "rank ") +
                                               std::to_string(share.rank) + "/" +
                                               std::to_string(share.size) + "]: "
                                         : "sweep: ";
  const auto prefix = [&](const control::SweepCase& c) {
    return who + c.name + " (" + std::to_string(c.index + 1) + "/" + std::to_string(n) + ", " +
           c.label() + "): ";
  };
  // One case ended: its line, the counts and the summary.
  const auto finished = [&](const Running& r, int code) {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - r.t0).count();
    const CaseState after = state_of(fs::path(plan.dir) / r.c->name);
    char buf[300];
    std::snprintf(buf, sizeof buf, "%s (exit %d, %.1f s", to_string(after.status), code, wall);
    std::string line = prefix(*r.c) + buf;
    if (after.end.found) {
      std::snprintf(buf, sizeof buf, ", %s, t=%g D=%.5f", after.end.reason.c_str(), after.end.t,
                    after.end.D);
      line += buf;
    }
    console::out(line + ")");
    if (code == exit_code::kUserError && !after.end.found)
      console::out("sweep: " + r.c->name + " did not start; see " +
                   (fs::path(plan.dir) / (r.c->name + ".log")).string());
    failed += code == exit_code::kSimulationFailed;
    output_failed += code == exit_code::kOutputFailed;
    if (a.only_case < 0) write_summary(plan, &known);
  };
  // Waits until a slot is free (max_running children at most), passing a stop signal on once.
  const auto wait_until = [&](size_t max_running) {
    while (running.size() > max_running) {
      if (stop->load() && !forwarded) {
        for (const Running& r : running) kill(r.pid, SIGTERM);
        forwarded = true;
      }
      for (size_t i = 0; i < running.size();) {
        int status = 0;
        if (waitpid(running[i].pid, &status, WNOHANG) == running[i].pid) {
          finished(running[i], exit_code_of_status(status));
          running.erase(running.begin() + static_cast<long>(i));
        } else {
          ++i;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  };
  for (const control::SweepCase& c : plan.cases) {
    if (a.only_case >= 0 && c.index != a.only_case) continue;
    if (c.index % share.size != share.rank) continue;
    wait_until(static_cast<size_t>(jobs) - 1);
    if (stop->load()) break;
    const CaseState before = state_of(fs::path(plan.dir) / c.name);
    if (before.status == CaseStatus::Done || before.status == CaseStatus::Failed) {
      console::out(prefix(c) + to_string(before.status) + " before, skipped");
      failed += before.status == CaseStatus::Failed;
      continue;
    }
    const bool resume = before.status == CaseStatus::Interrupted && before.has_checkpoint;
    console::out(prefix(c) + (resume ? "resuming" : "running") +
                 (groups ? " on " + std::to_string(parallel::size()) + " ranks" : ""));
    if (groups) {  // in this process, the group's other ranks serving it
      const Running r{0, &c, std::chrono::steady_clock::now()};
      reset_workers();
      int code = exit_code::kInternal;
      {
        const ConsoleTo log(fs::path(plan.dir) / (c.name + ".log"));
        code = run_command(case_run_args(plan, c, before));
      }
      finished(r, code);
      continue;
    }
    running.push_back({start_child(run_command_line(exe, case_run_args(plan, c, before)),
                                   fs::path(plan.dir) / (c.name + ".log"), threads),
                       &c, std::chrono::steady_clock::now()});
  }
  if (groups) end_workers();
  wait_until(0);
  if (a.only_case < 0) write_summary(plan, &known);
  if (stop->load())
    console::out("sweep: stopped by a signal; run capflow sweep " + a.file +
                 " again to continue");
  if (output_failed) return exit_code::kOutputFailed;
  if (failed) return exit_code::kSimulationFailed;
  return exit_code::kOk;
}

}  // namespace capflow::app
