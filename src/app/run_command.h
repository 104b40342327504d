// capflow/app/run_command: `capflow run` as a function: what the command line's `run` does, and
// what a sweep's group of MPI ranks runs for each of its cases (app/sweep.h).
#pragma once

#include <string>

#include "app/live_console.h"

namespace capflow::app {

struct RunArgs {
  std::string control;     // the control file (a new run)
  std::string output_dir;  // -o: overrides output.dir
  std::string resume;      // --resume RUN_DIR (then no control, -o or --overwrite)
  bool overwrite = false;
  double t_end = -1;  // --t-end (> 0): overrides time.t_end (with --resume: extends)
  ServeOptions serve;  // --serve, --serve-linger: the live console
};

// Runs it to its end (signals stop it as documented in cmd_run.cpp) and returns the exit code
// (app/errors.h); a failure is reported on stderr as the command line reports it.
int run_command(const RunArgs& args);

}  // namespace capflow::app
