// capflow/app/steady_run: `capflow steady` - steady shapes found directly, level by level.
//
// For pure straining flows (symmetric flow.gradient: planar, uniaxial, biaxial extension); a
// rotational flow is refused (UserError): its steady membrane tank-treads, use `capflow run`.
// Levels of Ca from the control file's "ca": a number, a list of holds ({"ca": x}) and steps
// ({"steps": {"to", "by"}}, from the level before; the first level from rest is `by`); a ramp
// has no levels and is refused. For each level, from the previous steady state (or from rest,
// or start.from):
//   1. approach: adaptive time steps (app::TimeStepper on "auto", time.tolerance) until the
//      largest node speed is below kApproachSpeed; the accepted steps there measure the
//      stability limit;
//   2. solve: capsule::solve_steady (Newton-Krylov on the midpoint step map, h = 0.5x those
//      steps);
//      when Newton does not converge, the approach goes on to a 4x smaller speed and the solve
//      is tried again (at most three times) before the level is reported as failed.
// Outputs, in a run directory like `capflow run`'s (app/run_directory.h: lock, --overwrite):
//   steady.csv  t,ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min (as `capflow run`'s)
//               then residual (max |F|, a G), speed (max node speed, a G: the volume leak's
//               dilation), volume_drift, newton, krylov, evaluations (velocity evaluations of
//               this level), wall_s, folds (the folds a continuation passed before this
//               state: odd, the state is on an unstable part of the branch, which a time march
//               leaves - within the mirror-symmetric shapes the solver works in; 0 for levels);
//               t is the simulated time the approaches took in all
//   checkpoints/ one per steady state (`start.from`, `capflow render`/`figure`, --resume of a
//               `capflow run`)      events.jsonl (start, steady, fold, edit, paused, resumed,
//               failure, branch_end, end)   run.log
// The first level from rest on NB > 8 is solved on NB=8 first and resampled (mesh sequencing:
// the long approach from the sphere at cheap evaluations). When the approach to a later level
// fails the health check, the branch has reached its resolution limit: it ends there, reported,
// with exit 0.
// A stop request (signal, or "run": {"state": "stopped"} saved in the control file) ends the
// branch at once: the level being solved is dropped, the states found are kept (exit 0).
// Live edits of the control file apply between states and approach steps: "ca" (a new list of
// levels replaces the levels beyond the last one solved; a continuation's to, step and
// after_fold), steady.solve_tolerance, time.tolerance and run.state
// ("paused" holds the run after the state being solved until "running" is saved); other keys
// are refused (events.jsonl "edit", as in capflow run).
#pragma once

#include <atomic>
#include <optional>
#include <string>

#include "control/options.h"

namespace capflow::app {

struct SteadySummary {
  int states = 0;       // steady states found
  bool failed = false;  // a level had no steady state (exit 4)
  // The branch ended at its resolution limit (exit 0): continued from a steady state, the time
  // steps to the next level failed the health check (the tips sharpen beyond what NB resolves).
  bool resolution_limit = false;
  std::optional<double> fold_ca;  // a continuation passed a fold there
  bool output_failed = false;
  std::string failure;
  double wall_s = 0;
  long evaluations = 0;
  int exit_code() const;
};

// The live control file: its path and its options as read (before command-line overrides,
// so that only keys saved with a new value count as edits).
struct SteadyControlFile {
  std::string path;
  control::ControlOptions options;
};

// UserError (exit 2): a rotational flow, a ramp, an occupied output directory. `stop`: set by
// a signal handler. `live`: the control file to watch (app/steady_control.h).
SteadySummary run_steady(const control::ControlOptions& options, bool overwrite,
                         const std::atomic<bool>* stop = nullptr,
                         const std::optional<SteadyControlFile>& live = std::nullopt);

}  // namespace capflow::app
