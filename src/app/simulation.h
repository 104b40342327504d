// capflow/app/simulation: the simulation driver behind `capflow run`.
//
// The run directory and every write into it belong to app/run_directory.h (layout, lock, whole
// records); what the run writes:
//   control.json       the effective control file (every key; rewritten after each accepted edit)
//   timeseries.csv     t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,
//                      inclination_deg,volume_drift,steps,wall_s   (every output.csv_every)
//   steady.csv         t,ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min: one row per
//                      steady state, with the time the steady test fired and the Ca held there
//   events.jsonl       one JSON object per event: start, start_from, resume, edit
//                      (accepted/refused, what changed), steady, level, warning, failure,
//                      checkpoint, pause, continue, end; each with wall_time (UTC) and t
//   run.log            the log lines also printed to stderr
//   frames/frame_NNNNNN.png, movie.mp4 (movie.partK.mp4 for the session after the (K-1)-th
//                      resume): every output.frame_every, from the renderer thread behind a
//                      bounded queue with back-pressure (frames are never dropped); NNNNNN is
//                      the frame index, which a resume continues; preview.png if render.preview
//   profiles/profile_NNNNNN.csv   z = 0 and y = 0 cross-sections at each frame time
//                      (header plane,t,a,b: plane z -> (a,b) = (x,y); plane y -> (x,z))
//   checkpoints/ckpt_SSSSSSSSSS.ckpt   at the start, every output.checkpoint_every, on
//                      run.checkpoint_now, on SIGINT/SIGTERM/SIGHUP and at the end (the three
//                      newest are kept); app/run_checkpoint.h is the codec
//   control.source     the path of the live control file being watched
//
// A run loop iteration has four parts, one job each: apply_edits (the live control file),
// advance (one step and the health check), observe (diagnostics and the Ca schedule's
// steady-state test) and emit (the outputs that are due).
// Steering: the control file is watched (control/watcher.h); an edit applies at the next step
// boundary under the policy of control/edit.h and is logged in events.jsonl.
// Ends at t_end, on a stop request (a signal: the current step is finished, a checkpoint
// written, the movie finalised), on "run.state": "stopped", on a failure of the simulation
// (health monitor: the last good state is kept and checkpointed; exit 4) or of an output
// (a file that cannot be written: the run stops, the last good checkpoint is kept; exit 5).
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "control/options.h"

namespace capflow::app {

struct RunSummary {
  bool failed = false;         // the simulation failed (exit 4)
  bool output_failed = false;  // a run file could not be written (exit 5)
  std::string failure;         // message when failed or output_failed
  std::string reason;          // why the run ended
  double t = 0;
  long steps = 0;
  long evaluations = 0;        // velocity evaluations in this session
  long krylov_iterations = 0;  // GMRES iterations of the viscosity-ratio solves (lambda != 1)
  double wall_s = 0;
  double D = 0, L = 0, S = 0, W = 0;
  double volume_drift = 0;
  int steady_states = 0;
  int exit_code() const;  // app/errors.h
};

// A new run.
struct NewRun {
  control::ControlOptions options;       // effective: command-line overrides applied
  control::ControlOptions file_options;  // as the control file says: the base of live edits
  std::string control_source;            // the control file to watch ("" = none)
  bool overwrite = false;                // replace an existing run in options.output.dir
};

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

  // Path of the newest checkpoint in a run directory ("" if none).
  static std::string latest_checkpoint(const std::string& run_dir);

 private:
  Simulation();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace capflow::app
