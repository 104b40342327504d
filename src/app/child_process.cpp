// capflow/app/child_process: see child_process.h.
#include "app/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <stdexcept>

#include "app/console.h"
#include "app/errors.h"

extern char** environ;

namespace capflow::app {

namespace fs = std::filesystem;

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the capflow executable: " + ec.message());
  return p.string();
}

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

int exit_code_of_status(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

ConsoleTo::ConsoleTo(const fs::path& log) {
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

ConsoleTo::~ConsoleTo() {
  flush_all();
  restore();
}

void ConsoleTo::flush_all() {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
}

// The console back, and the streams usable again (a full disk under the log set their error
// state, which would silence the sweep's own report).
void ConsoleTo::restore() {
  if (out_ >= 0) ::dup2(out_, 1), ::close(out_);
  if (err_ >= 0) ::dup2(err_, 2), ::close(err_);
  out_ = err_ = -1;
  std::cout.clear();
  std::cerr.clear();
  std::clearerr(stdout);
  std::clearerr(stderr);
  console::reset();
}

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

}  // namespace capflow::app
