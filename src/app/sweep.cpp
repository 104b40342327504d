#include "app/sweep.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>
#include <vector>

#include "app/console.h"
#include "app/errors.h"
#include "app/run_command.h"
#include "app/run_directory.h"
#include "app/stop_signal.h"
#include "app/worker_team.h"
#include "control/control_error.h"
#include "control/limits.h"
#include "control/run_events.h"
#include "control/sweep.h"
#include "files/atomic_write.h"
#include "files/input_file.h"
#include "parallel/team.h"

extern char** environ;

namespace capflow::app {

namespace fs = std::filesystem;

namespace {

enum class Status { New, Done, Failed, Interrupted };

const char* to_string(Status s) {
  switch (s) {
    case Status::New:
      return "new";
    case Status::Done:
      return "done";
    case Status::Failed:
      return "failed";
    case Status::Interrupted:
      return "interrupted";
  }
  return "";
}

struct CaseState {
  Status status = Status::New;
  control::RunEnd end;
  bool has_checkpoint = false;
};

CaseState state_of(const fs::path& run) {
  CaseState s;
  if (!RunDirectory::is_run(run)) return s;
  s.end = control::last_run_end((run / "events.jsonl").string());
  s.has_checkpoint = !RunDirectory::checkpoints(run).empty();
  if (s.end.found && s.end.exit_code == exit_code::kOk && s.end.reason != "stopped by signal")
    s.status = Status::Done;
  else if (s.end.found && s.end.exit_code == exit_code::kSimulationFailed)
    s.status = Status::Failed;
  else
    s.status = Status::Interrupted;
  return s;
}

// A case control file as the sweep wrote it (files/input_file.h's rule).
std::string read_text(const fs::path& p) {
  try {
    return files::read_input_file(p.string(), "case control file", control::kMaxControlBytes);
  } catch (const files::InputError& e) {
    throw UserError(e.what());
  }
}

// Replaces p with text (a temporary file of this process, renamed); OutputError naming p.
void write_atomically(const fs::path& p, const std::string& text) {
  try {
    files::write_atomically(p.string(), text, {/*sync=*/false, /*unique_temp=*/true});
  } catch (const files::WriteError& e) {
    throw OutputError(e.what());
  }
}

// The names a sweep writes in its directory: case_NNN.json, case_NNN/, case_NNN.log, sweep.csv
// (and its lock), sweep.sbatch, slurm_N.out, and temporary files of its atomic writes.
bool sweep_entry(const std::string& name) {
  const auto digits_between = [&](const std::string& pre, const std::string& post) {
    if (name.size() <= pre.size() + post.size() || name.compare(0, pre.size(), pre) != 0 ||
        name.compare(name.size() - post.size(), post.size(), post) != 0)
      return false;
    for (size_t i = pre.size(); i < name.size() - post.size(); ++i)
      if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
    return true;
  };
  if (name == "sweep.csv" || name == "sweep.csv.lock" || name == "sweep.sbatch") return true;
  if (digits_between("case_", "") || digits_between("case_", ".json") ||
      digits_between("case_", ".log") || digits_between("slurm_", ".out"))
    return true;
  return name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0 &&
         (name.rfind("sweep.", 0) == 0 || name.rfind("case_", 0) == 0);
}

// True when sweep.csv in `dir` is a capflow sweep's summary (its header).
bool capflow_summary(const fs::path& csv) {
  try {
    const std::string head = files::InputFile(csv.string(), "sweep summary", 64 << 20).read_prefix(4096);
    const std::string line = head.substr(0, head.find('\n'));
    const std::string tail = ",status,exit_code,reason,t,D,L,S,W,steps,dir";
    return line.rfind("case,", 0) == 0 && line.size() >= tail.size() &&
           line.compare(line.size() - tail.size(), tail.size(), tail) == 0;
  } catch (const files::InputError&) {
    return false;
  }
}

// The sweep directory before anything is written into it, by run's rules: a new or empty
// directory, or one that holds a capflow sweep (re-running it continues it, whatever else the
// user keeps beside it); a directory with only other things in it is refused unless --overwrite, and even then a file of the user's in a
// place the sweep writes (a sweep.csv that is not a capflow summary) is refused: capflow never
// replaces what it did not write. --overwrite on a sweep removes the sweep's own entries, so it
// starts afresh.
void prepare_sweep_directory(const control::SweepPlan& plan, bool overwrite) {
  const fs::path dir(plan.dir);
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw UserError("output.dir " + plan.dir + " exists and is not a directory");
  std::vector<std::string> foreign;
  bool ours = false;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!sweep_entry(name)) {
      foreign.push_back(name);
    } else if (name == "sweep.csv" && !capflow_summary(e.path())) {
      throw UserError("output.dir " + plan.dir + " holds a sweep.csv that is not a capflow sweep's "
                      "summary: capflow would replace it; give the sweep another output.dir");
    } else {
      ours = true;
    }
  }
  if (!foreign.empty() && !ours && !overwrite) {
    std::string names;
    for (size_t i = 0; i < foreign.size() && i < 3; ++i) names += (i ? ", " : "") + foreign[i];
    throw UserError("output.dir " + plan.dir + " is not empty and is not a capflow sweep (it holds " +
                    names + (foreign.size() > 3 ? ", ..." : "") +
                    "): give a new or empty directory, or --overwrite to write the sweep beside "
                    "what is there (nothing of it is removed)");
  }
  if (overwrite && ours) {
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (sweep_entry(e.path().filename().string())) fs::remove_all(e.path(), ec);
  }
}

// The case control files: written when absent, refused when they differ from the sweep's.
void write_case_files(const control::SweepPlan& plan) {
  std::error_code ec;
  fs::create_directories(plan.dir, ec);
  if (ec) throw UserError("cannot create the sweep directory " + plan.dir + ": " + ec.message());
  for (const control::SweepCase& c : plan.cases) {
    const fs::path p = fs::path(plan.dir) / (c.name + ".json");
    if (fs::exists(p)) {
      if (read_text(p) != c.control_text)
        throw UserError(p.string() + " differs from " + c.name + " of this sweep file (" +
                        c.label() +
                        "): the sweep changed since that case was made; give the sweep another "
                        "output.dir, or remove " +
                        plan.dir);
      continue;
    }
    write_atomically(p, c.control_text);
  }
}

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the capflow executable: " + ec.message());
  return p.string();
}

// Starts `capflow args...` with stdout and stderr appended to log, in its own process group (a
// terminal's signals reach the sweep only, which passes them on), without the MPI launcher's
// environment, with OMP_NUM_THREADS = threads when threads > 0. Returns the child's pid.
pid_t start_child(const std::vector<std::string>& args, const fs::path& log, int threads) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawnattr_t at;
  posix_spawnattr_init(&at);
  posix_spawnattr_setpgroup(&at, 0);
  sigset_t def;
  sigemptyset(&def);
  sigaddset(&def, SIGINT);
  sigaddset(&def, SIGTERM);
  sigaddset(&def, SIGHUP);
  posix_spawnattr_setsigdefault(&at, &def);
  posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // the environment, with OMP_NUM_THREADS replaced when the sweep divides the cores
  std::vector<std::string> env_text;
  // and without the MPI launcher's variables: a case is one process (under them `capflow run`
  // would join the launcher's job as one of its ranks)
  const auto launcher = [](const char* e) {
    for (const char* p :
         {"OMPI_", "PMIX_", "PMI_", "MPI_LOCALNRANKS", "MPI_LOCALRANKID", "SLURM_STEP_NUM_TASKS"})
      if (std::strncmp(e, p, std::strlen(p)) == 0) return true;
    return false;
  };
  for (char** e = environ; *e; ++e)
    if (!launcher(*e) && (threads <= 0 || std::strncmp(*e, "OMP_NUM_THREADS=", 16) != 0))
      env_text.emplace_back(*e);
  if (threads > 0) env_text.push_back("OMP_NUM_THREADS=" + std::to_string(threads));
  std::vector<char*> envp;
  for (std::string& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &fa, &at, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  if (rc != 0) throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(rc));
  return pid;
}

// The exit code of a finished child's wait status (128 + the signal if it was killed).
int exit_code_of(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// What continues case c: resume an interrupted run that has a checkpoint, else start it afresh.
RunArgs case_run_args(const control::SweepPlan& plan, const control::SweepCase& c,
                      const CaseState& state) {
  const fs::path run = fs::path(plan.dir) / c.name;
  RunArgs r;
  if (state.status == Status::Interrupted && state.has_checkpoint) {
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

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// Holds an exclusive flock on a file for its life (sweep.csv.lock: the summary is read from the
// case directories and written under it, so that of several launcher ranks the last one to
// write read last, after every other rank's cases ended).
class FileLock {
 public:
  explicit FileLock(const fs::path& p)
      : fd_(::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    if (fd_ < 0) throw OutputError("cannot open " + p.string() + ": " + std::strerror(errno));
    while (flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
    }
  }
  ~FileLock() { ::close(fd_); }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// The cases' states: done and failed are final and kept; the others are read again from their
// run directories (events.jsonl) at each summary, since other ranks may have moved them on.
struct KnownStates {
  std::vector<CaseState> states;
  const CaseState& refresh(size_t i, const fs::path& run) {
    if (states.size() <= i) states.resize(i + 1);
    CaseState& s = states[i];
    if (s.status != Status::Done && s.status != Status::Failed) s = state_of(run);
    return s;
  }
};

void write_summary(const control::SweepPlan& plan, KnownStates* known) {
  const FileLock lock(fs::path(plan.dir) / "sweep.csv.lock");
  std::ostringstream out;
  out << "case";
  for (const std::string& k : plan.keys) out << "," << csv_field(k);
  out << ",status,exit_code,reason,t,D,L,S,W,steps,dir\n";
  for (const control::SweepCase& c : plan.cases) {
    const fs::path run = fs::path(plan.dir) / c.name;
    const CaseState& s = known->refresh(static_cast<size_t>(c.index), run);
    out << c.index;
    for (const auto& [k, v] : c.values) out << "," << csv_field(v);
    out << "," << to_string(s.status);
    if (s.end.found) {
      char buf[256];
      std::snprintf(buf, sizeof buf, ",%d,%s,%.10g,%.10g,%.10g,%.10g,%.10g,%ld", s.end.exit_code,
                    csv_field(s.end.reason).c_str(), s.end.t, s.end.D, s.end.L, s.end.S, s.end.W,
                    s.end.steps);
      out << buf;
    } else {
      out << ",,,,,,,,";
    }
    out << "," << csv_field(run.string()) << "\n";
  }
  write_atomically(fs::path(plan.dir) / "sweep.csv", out.str());
}

void write_slurm(const control::SweepPlan& plan, const std::string& sweep_file) {
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# capflow sweep " << sweep_file << ": one Slurm array task per case (" << plan.cases.size()
    << " cases). Submit with: sbatch " << (fs::path(plan.dir) / "sweep.sbatch").string() << "\n"
    << "# Afterwards: capflow sweep " << sweep_file << " --summary  (writes sweep.csv)\n"
    << "#SBATCH --job-name=capflow-sweep\n"
    << "#SBATCH --array=0-" << plan.cases.size() - 1 << "\n"
    << "#SBATCH --cpus-per-task=2\n"
    << "#SBATCH --output=" << (fs::path(plan.dir) / "slurm_%a.out").string() << "\n"
    << "export OMP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-2}\n"
    << "cd " << fs::current_path().string() << "\n"
    << "exec " << self_exe() << " sweep " << sweep_file << " --case \"$SLURM_ARRAY_TASK_ID\"\n";
  write_atomically(fs::path(plan.dir) / "sweep.sbatch", s.str());
}

// This process's share of the cases when an MPI launcher (mpirun, or srun) started several:
// cases with index % size == rank. The rank and size come from the launcher's environment
// (Open MPI, MPICH/PMI, Slurm), so no MPI library is needed: the cases do not communicate.
struct Share {
  int rank = 0, size = 1;
};

Share launcher_share() {
  const char* pairs[][2] = {{"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"},
                            {"PMI_RANK", "PMI_SIZE"},
                            {"SLURM_PROCID", "SLURM_NTASKS"}};
  for (const auto& p : pairs) {
    const char* r = std::getenv(p[0]);
    const char* n = std::getenv(p[1]);
    if (!r || !n) continue;
    Share s{std::atoi(r), std::atoi(n)};
    if (s.size >= 1 && s.rank >= 0 && s.rank < s.size) return s;
  }
  return {};
}

// The console (stdout and stderr) appended to a file while it lives: a case run in this process
// writes its lines to its case_NNN.log as a child process would.
class ConsoleTo {
 public:
  explicit ConsoleTo(const fs::path& log) {
    flush_all();
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw OutputError("cannot write " + log.string() + ": " + std::strerror(errno));
    // the console kept aside, not inherited by what the case starts (the movie encoder)
    out_ = ::fcntl(1, F_DUPFD_CLOEXEC, 3);
    err_ = ::fcntl(2, F_DUPFD_CLOEXEC, 3);
    if (out_ < 0 || err_ < 0 || ::dup2(fd, 1) < 0 || ::dup2(fd, 2) < 0) {
      const int e = errno;
      ::close(fd);
      restore();
      throw OutputError("cannot send the console to " + log.string() + ": " + std::strerror(e));
    }
    ::close(fd);
    console::reset();
  }
  ~ConsoleTo() {
    flush_all();
    restore();
  }
  ConsoleTo(const ConsoleTo&) = delete;
  ConsoleTo& operator=(const ConsoleTo&) = delete;

 private:
  static void flush_all() {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
  }
  // The console back, and the streams usable again (a full disk under the log set their error
  // state, which would silence the sweep's own report).
  void restore() {
    if (out_ >= 0) ::dup2(out_, 1), ::close(out_);
    if (err_ >= 0) ::dup2(err_, 2), ::close(err_);
    out_ = err_ = -1;
    std::cout.clear();
    std::cerr.clear();
    std::clearerr(stdout);
    std::clearerr(stderr);
    console::reset();
  }

  int out_ = -1, err_ = -1;
};

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
  control::SweepPlan plan;
  try {
    plan = control::load_sweep_file(a.file);
  } catch (const control::ControlError& e) {
    throw UserError(e.what());
  }
  const int n = static_cast<int>(plan.cases.size());
  if (a.only_case >= n)
    throw UserError("--case " + std::to_string(a.only_case) + ": the sweep has cases 0 to " +
                    std::to_string(n - 1));
  check_sweep_args(a, launcher_share().size);
  if (a.only_case < 0 && !a.summary) prepare_sweep_directory(plan, a.overwrite);
  write_case_files(plan);
  if (a.slurm) {
    write_slurm(plan, a.file);
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
          finished(running[i], exit_code_of(status));
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
    if (before.status == Status::Done || before.status == Status::Failed) {
      console::out(prefix(c) + to_string(before.status) + " before, skipped");
      failed += before.status == Status::Failed;
      continue;
    }
    const bool resume = before.status == Status::Interrupted && before.has_checkpoint;
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
