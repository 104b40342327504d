// capflow/app/simulation: the simulation driver behind `capflow run`.
//
// Owns the run directory and all run I/O (the solver modules do none):
//   control.json       the effective control file (every key; rewritten after each accepted edit)
//   timeseries.csv     t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,
//                      inclination_deg,volume_drift,steps,wall_s   (every output.csv_every)
//   steady.csv         ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min (per steady state)
//   events.jsonl       one JSON object per event: start, start_from, resume, edit (accepted/refused, what
//                      changed), steady, level, warning, failure, checkpoint, pause, end; each
//                      with wall_time (UTC) and t (simulated time)
//   run.log            the log lines also printed to stderr
//   frames/frame_NNNNNN.png, movie.mp4 (movie.partK.mp4 after the K-th resume): every
//                      output.frame_every, from the renderer thread behind a bounded queue with
//                      back-pressure (frames are never dropped); preview.png if render.preview
//   profiles/profile_NNNNNN.csv   z = 0 and y = 0 cross-sections at each frame time
//                      (header plane,t,a,b: plane z -> (a,b) = (x,y); plane y -> (x,z))
//   checkpoints/ckpt_SSSSSSSSSS.ckpt   every output.checkpoint_every, on run.checkpoint_now,
//                      on SIGINT/SIGTERM and at the end (the three newest are kept)
//   control.source     the path of the live control file being watched
// Steering: the control file is watched (control/watcher.h); an edit applies at the next step
// boundary under the policy of control/edit.h and is logged in events.jsonl.
// Ends at t_end, on a stop request (SIGINT/SIGTERM: the current step is finished, a checkpoint
// written, the movie finalised), on "run.state": "stopped", or on a failure (health monitor):
// then the last good state is kept and checkpointed, and the message names cause, time, place.
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "control/options.h"

namespace capflow::app {

struct RunSummary {
  bool failed = false;
  std::string failure;  // message when failed
  std::string reason;   // why the run ended
  double t = 0;
  long steps = 0;
  double wall_s = 0;
  double D = 0, L = 0, S = 0, W = 0;
  double volume_drift = 0;
  int steady_states = 0;
};

struct ResumeOverrides {
  std::optional<double> t_end;  // continue to this time instead of the stored t_end
};

class Simulation {
 public:
  // A new run. `control_source` is the control file to watch for live edits ("" = none).
  Simulation(const control::ControlOptions& options, const std::string& control_source);
  // Continues the run in `run_dir` from its newest checkpoint. Throws std::runtime_error (with
  // the file named) when there is no usable checkpoint or it does not match the run.
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
