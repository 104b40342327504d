// Helpers of the second hostile-input round's tests (Milestone 17): the capflow executable run
// with its console on a closed pipe, under resource limits, or signalled at a chosen moment, and
// the small runs they drive.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "process_util.h"

namespace capflow::test {

struct Limits {
  long file_size = -1;     // RLIMIT_FSIZE bytes (a write past it fails as on a full disk)
  long address_space = -1; // RLIMIT_AS bytes (thread stacks and allocations)
  bool closed_console = false;  // stdout and stderr a pipe whose reader is gone
};

// Starts capflow `args` (CAPFLOW_EXE prepended) with stderr to `log` (or to a closed pipe).
inline pid_t start_capflow(const std::vector<std::string>& args, const std::filesystem::path& log,
                           const Limits& lim = {}) {
  std::vector<std::string> all = {CAPFLOW_EXE};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  int p[2] = {-1, -1};
  if (lim.closed_console && ::pipe(p) != 0) return -1;
  const pid_t pid = fork();
  if (pid == 0) {
    if (lim.closed_console) {
      ::close(p[0]);  // nobody reads: every write gets EPIPE (and SIGPIPE unless ignored)
      dup2(p[1], 1);
      dup2(p[1], 2);
    } else {
      const int err = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int out = ::open("/dev/null", O_WRONLY);
      if (err >= 0) dup2(err, 2);
      if (out >= 0) dup2(out, 1);
    }
    if (lim.file_size >= 0) {
      struct rlimit r;
      r.rlim_cur = r.rlim_max = static_cast<rlim_t>(lim.file_size);
      setrlimit(RLIMIT_FSIZE, &r);
    }
    if (lim.address_space >= 0) {
      struct rlimit r;
      r.rlim_cur = r.rlim_max = static_cast<rlim_t>(lim.address_space);
      setrlimit(RLIMIT_AS, &r);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
  if (lim.closed_console) {
    ::close(p[0]);
    ::close(p[1]);
  }
  return pid;
}

inline int capflow(const std::vector<std::string>& args, const std::filesystem::path& log,
                   const Limits& lim = {}, double seconds = 120) {
  return wait_exit(start_capflow(args, log, lim), seconds);
}

// A small run: NE=6 NB=6, Ca 0.3 in planar extension, adaptive steps to t_end, a row every
// csv_every; `output` and `extra` add keys ("output" must be an object's inside, without braces).
inline std::string small_run(double t_end, const std::string& output = "",
                             const std::string& extra = "") {
  std::ostringstream s;
  s << R"({"mesh": {"elements": 6, "nb": 6}, "ca": 0.3, "time": {"t_end": )" << t_end
    << R"(}, "output": {"csv_every": 0.02)" << (output.empty() ? "" : ", " + output) << "}"
    << (extra.empty() ? "" : ", " + extra) << "}";
  return s.str();
}

// The lines of a CSV without its last column (wall_s: the only one that differs between two
// runs of the same state).
inline std::vector<std::string> rows_without_wall(const std::filesystem::path& csv) {
  std::vector<std::string> out;
  for (const std::string& l : lines_of(csv)) out.push_back(l.substr(0, l.rfind(',')));
  return out;
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The exit code of `capflow args`, with its log for messages.
struct Outcome {
  int code;
  std::string log;
};
inline Outcome outcome(const std::vector<std::string>& args, const std::filesystem::path& dir,
                       const Limits& lim = {}) {
  const std::filesystem::path log = dir / "outcome.log";
  const int code = capflow(args, log, lim);
  return {code, read_file(log)};
}

}  // namespace capflow::test
