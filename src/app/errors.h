// capflow/app/errors: the error classes of the capflow executable and their exit codes.
//
//   0  success
//   2  invalid input: control file, command line, start.from, output directory, checkpoint
//      (UserError; the message names the file, key or option, the bad value and what is valid)
//   3  internal error (a bug: anything that is not one of the others)
//   4  the simulation failed (health check or solver; the last good state is checkpointed)
//   5  a run file could not be written (OutputError: disk full, file too large, permissions;
//      the message names the file; the last good checkpoint is kept, and --resume continues
//      with consistent files once the cause is removed)
#pragma once

#include <stdexcept>
#include <string>

namespace capflow::app {

namespace exit_code {
constexpr int kOk = 0;
constexpr int kUserError = 2;
constexpr int kInternal = 3;
constexpr int kSimulationFailed = 4;
constexpr int kOutputFailed = 5;
}  // namespace exit_code

// The exit code of a command that ran: an output failure before a failed computation.
inline int outcome_exit_code(bool failed, bool output_failed) {
  if (output_failed) return exit_code::kOutputFailed;
  if (failed) return exit_code::kSimulationFailed;
  return exit_code::kOk;
}

struct UserError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The exit code of an exception that ends a command: UserError, control::ControlError and
// files::InputError (a file or input that cannot be used) 2; OutputError and files::WriteError
// (a file that cannot be written) 5; anything else 3.
int exit_code_of(const std::exception& e);

// Prints what went wrong as capflow reports it ("capflow: error: ...", "capflow: output error:
// ...", "capflow: internal error: ..."; app/console.h) and returns exit_code_of(e).
int report_failure(const std::exception& e);

}  // namespace capflow::app
