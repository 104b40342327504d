// capflow/app/sweep_directory: see sweep_directory.h.
#include "app/sweep_directory.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "app/errors.h"
#include "app/run_directory.h"
#include "control/limits.h"
#include "files/atomic_write.h"
#include "files/input_file.h"

namespace capflow::app {

namespace fs = std::filesystem;

namespace {

// The sweep's own files are replaced through a temporary file of this process (several launcher
// ranks may write them at once).
const files::AtomicWrite kCaseWrite{/*sync=*/false, /*unique_temp=*/true};

// A case control file as the sweep wrote it (files/input_file.h's rule).
std::string read_text(const fs::path& p) {
  try {
    return files::read_input_file(p.string(), "case control file", control::kMaxControlBytes);
  } catch (const files::InputError& e) {
    throw UserError(e.what());
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

}  // namespace

const char* to_string(CaseStatus s) {
  switch (s) {
    case CaseStatus::New:
      return "new";
    case CaseStatus::Done:
      return "done";
    case CaseStatus::Failed:
      return "failed";
    case CaseStatus::Interrupted:
      return "interrupted";
  }
  return "";
}


CaseState state_of(const fs::path& run) {
  CaseState s;
  if (!RunDirectory::is_run(run)) return s;
  s.end = control::last_run_end((run / "events.jsonl").string());
  s.has_checkpoint = !RunDirectory::checkpoints(run).empty();
  if (s.end.found && s.end.exit_code == exit_code::kOk && s.end.reason != "stopped by signal")
    s.status = CaseStatus::Done;
  else if (s.end.found && s.end.exit_code == exit_code::kSimulationFailed)
    s.status = CaseStatus::Failed;
  else
    s.status = CaseStatus::Interrupted;
  return s;
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
    files::write_atomically(p.string(), c.control_text, kCaseWrite);
  }
}

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
  files::write_atomically((fs::path(plan.dir) / "sweep.csv").string(), out.str(), kCaseWrite);
}

void write_slurm(const control::SweepPlan& plan, const std::string& sweep_file,
                 const std::string& exe) {
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
    << "exec " << exe << " sweep " << sweep_file << " --case \"$SLURM_ARRAY_TASK_ID\"\n";
  files::write_atomically((fs::path(plan.dir) / "sweep.sbatch").string(), s.str(), kCaseWrite);
}


}  // namespace capflow::app
