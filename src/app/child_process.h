// capflow/app/child_process: the processes a sweep starts (app/sweep.h) - capflow itself, a case
// per child with its console in the case's log - and, for a case it runs in its own process, that
// console redirected; the share of the cases an MPI launcher gives this process.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace capflow::app {

// The path of the running capflow executable (std::runtime_error when /proc does not tell).
std::string self_exe();

// Starts `capflow args...` with stdout and stderr appended to log, in its own process group (a
// terminal's signals reach the sweep only, which passes them on), without the MPI launcher's
// environment, with OMP_NUM_THREADS = threads when threads > 0. Returns the child's pid.
pid_t start_child(const std::vector<std::string>& args, const std::filesystem::path& log,
                  int threads);

// The exit code of a finished child's wait status (128 + the signal if it was killed).
int exit_code_of_status(int status);

// The console (stdout and stderr) appended to a file while it lives: a case run in this process
// writes its lines to its case_NNN.log as a child process would. OutputError when it cannot.
class ConsoleTo {
 public:
  explicit ConsoleTo(const std::filesystem::path& log);
  ~ConsoleTo();
  ConsoleTo(const ConsoleTo&) = delete;
  ConsoleTo& operator=(const ConsoleTo&) = delete;

 private:
  static void flush_all();
  void restore();
  int out_ = -1, err_ = -1;
};

// This process's share of the cases when an MPI launcher (mpirun, or srun) started several:
// cases with index % size == rank. The rank and size come from the launcher's environment
// (Open MPI, MPICH/PMI, Slurm), so no MPI library is needed: the cases do not communicate.
struct Share {
  int rank = 0, size = 1;
};
Share launcher_share();

}  // namespace capflow::app
