// capflow/app/simulation: the loop of `capflow run` - time steps of the capsule under the Ca
// schedule, with its live edits. Everything around the loop is the run's lifecycle
// (app/run_lifecycle.h: the run directory, start.from and resume, the renderer, pauses, the
// live control file, the end) and its outputs are observers of the states it reports
// (app/run_outputs.h: rows, frames, profiles, surfaces; checkpoints, app/run_checkpoint.h).
//
// A loop iteration has four parts, one job each: edits (the live control file, applied under
// capflow run's policy: every live key, a continuation refused), advance (one step and the
// health check), observe (diagnostics and the Ca schedule's steady-state test) and emit (the
// outputs that are due). It ends at t_end, on a stop request (a signal: the current step is
// finished, a checkpoint written, the movie finalised), on "run.state": "stopped", at the steady
// state of the final level with steady.stop, on a failure of the simulation (health monitor: the
// last good state is kept and checkpointed; exit 4) or of an output (a file that cannot be
// written: the run stops, the last good checkpoint is kept; exit 5).
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "app/run_lifecycle.h"
#include "app/run_outputs.h"
#include "app/run_summary.h"
#include "control/options.h"

namespace capflow::app {

struct ResumeOverrides {
  std::optional<double> t_end;  // continue to this time instead of the stored t_end
};

class Simulation {
 public:
  // Refuses (UserError, nothing created) a bad start.from, a schedule that cannot start, an
  // occupied or foreign output directory; OutputError when the run directory cannot be written.
  explicit Simulation(const NewRun& run);
  // A new run without a control file to watch (file_options = options).
  Simulation(const control::ControlOptions& options, const std::string& control_source);
  // Continues the run in `run_dir` from its newest checkpoint that reads (falling back to older
  // ones, and saying so). UserError (exit 2) when there is none, or t_end is not after it.
  static std::unique_ptr<Simulation> resume(const std::string& run_dir, const ResumeOverrides& o);
  ~Simulation();

  // Runs to completion. `stop` may be set from a signal handler.
  RunSummary run(const std::atomic<bool>* stop = nullptr);

  // The lifecycle and the outputs (their observers: the live console).
  RunLifecycle& lifecycle();
  RunOutputs& outputs();
  // The run's options before it runs (live edits change them later, in the run's thread).
  const control::ControlOptions& options() const;

  // Path of the newest checkpoint in a run directory ("" if none).
  static std::string latest_checkpoint(const std::string& run_dir);

 private:
  Simulation();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace capflow::app
