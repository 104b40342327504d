// capflow/app/steady_outputs: what capflow steady writes for each steady state it finds - the
// observers of its states, as app/run_outputs.h's are capflow run's:
//   steady.csv    a row (output/records.h: steady_solve())
//   checkpoints/  the state as a run held at its Ca (start.from, render, figure, --resume)
//   frames        one per state (output.png, output.mp4; app/frames.h), and the preview
//   run.log       its line, and warnings for a root the grid does not resolve (compressive
//                 tension: wrinkles; node-to-node oscillation above the time steps' limit)
//   events.jsonl  "steady" (with its checkpoint), "warning"
// and, when a level fails, its last good state kept as a checkpoint.
#pragma once

#include <string>

#include "app/level_solver.h"
#include "app/run_lifecycle.h"
#include "capsule/steady_solver.h"
#include "control/options.h"
#include "diagnostics/diagnostics.h"

namespace capflow::app {

// A steady state on the fine grid (its x) as the solvers found it.
struct SteadyState {
  double ca = 0;
  const capsule::SteadySolution* solution = nullptr;  // residual, speed
  int newton = 0;
  long krylov = 0;
  long evaluations = 0;  // velocity evaluations of this state, on every grid
  double wall_s = 0;     // wall seconds it took
  int folds = 0;         // folds the continuation passed before it
  double t = 0;          // simulated time of every approach so far
  long steps = 0;        // time steps of every approach so far
};

class SteadyOutputs {
 public:
  // `options`: the run's (read at each state); `fine`: the grid the states are on.
  SteadyOutputs(RunLifecycle& life, const control::ControlOptions& options, const Grid& fine);

  void write(const SteadyState& s);
  // A level failed at `ca` (exit 4): its last good state is kept - the last steady state (its
  // checkpoint is there), else the fine grid's capsule as the failed march left it.
  void keep_last_good_state(double ca, long steps);
  // The renderer's end and its line.
  void finish_frames();

  long states() const { return states_; }

 private:
  void submit_frame(double ca, double t, const diagnostics::ShapeDiagnostics& d,
                    double tau_max, double tau_min);
  bool frames_wanted() const;
  void warn(const std::string& cause, double ca, const char* key, double value,
            const std::string& message, double t);
  void warn_if_compressed(double ca, double tau_min, double t);
  void warn_if_oscillating(double ca, double amplitude, double t);
  std::string write_checkpoint(double ca, const Eigen::Matrix3Xd& x, double t, long steps,
                               const std::string& note);

  RunLifecycle& life_;
  const control::ControlOptions& opt_;
  const Grid& fine_;
  long frames_ = 0;
  long states_ = 0;  // checkpoints written
};

}  // namespace capflow::app
