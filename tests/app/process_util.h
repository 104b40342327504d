// Helpers for the app tests that drive the capflow executable: start it (optionally with a
// file-size limit, which makes writes fail like a full disk), wait for its exit code, read its
// events.jsonl and CSV files.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_util.h"

namespace capflow::test {

// Starts `args` (args[0] the executable) with stderr to `log`, stdout to /dev/null. With
// `file_size_limit` >= 0 bytes, RLIMIT_FSIZE is set in the child: a write past it fails with
// EFBIG (capflow ignores SIGXFSZ), as on a full disk.
inline pid_t spawn(const std::vector<std::string>& args, const std::filesystem::path& log,
                   long file_size_limit = -1) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int err = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int out = ::open("/dev/null", O_WRONLY);
    if (err >= 0) dup2(err, 2);
    if (out >= 0) dup2(out, 1);
    if (file_size_limit >= 0) {
      struct rlimit r;
      r.rlim_cur = r.rlim_max = static_cast<rlim_t>(file_size_limit);
      setrlimit(RLIMIT_FSIZE, &r);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

// The exit code (128 + signal when killed); -1 if it did not end within `seconds` (then killed).
inline int wait_exit(pid_t pid, double seconds) {
  int status = 0;
  const bool done = wait_for([&] { return waitpid(pid, &status, WNOHANG) == pid; }, seconds);
  if (!done) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Runs to the end; returns the exit code.
inline int run_capflow(const std::vector<std::string>& args, const std::filesystem::path& log,
                       double seconds = 120, long file_size_limit = -1) {
  return wait_exit(spawn(args, log, file_size_limit), seconds);
}

inline std::vector<nlohmann::json> events(const std::filesystem::path& run) {
  std::vector<nlohmann::json> out;
  for (const auto& l : lines_of(run / "events.jsonl"))
    if (!l.empty()) out.push_back(nlohmann::json::parse(l));
  return out;
}

inline int count_events(const std::filesystem::path& run, const std::string& kind) {
  int n = 0;
  for (const auto& e : events(run)) n += e["event"] == kind;
  return n;
}

inline long csv_rows(const std::filesystem::path& p) {
  return static_cast<long>(lines_of(p).size()) - 1;
}

}  // namespace capflow::test
