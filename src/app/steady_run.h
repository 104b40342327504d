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
// The solving is app/level_solver.h's (levels) and app/branch_follower.h's (a continuation);
// this driver keeps the levels' loop, the live edits it takes and what it writes, in a run
// directory whose life is app/run_lifecycle.h's, as capflow run's is.
// Outputs, in a run directory like `capflow run`'s (app/run_directory.h: lock, --overwrite):
//   steady.csv  t,ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min (as `capflow run`'s)
//               then residual (max |F|, a G), speed (max node speed, a G: the volume leak's
//               dilation), volume_drift, newton, krylov, evaluations (velocity evaluations of
//               this level), wall_s, folds (the folds a continuation passed before this
//               state: odd, the state is on an unstable part of the branch, which a time march
//               leaves - within the mirror-symmetric shapes the solver works in; 0 for levels);
//               t is the simulated time the approaches took in all
//   checkpoints/ one per steady state (`start.from`, `capflow render`/`figure`, --resume of a
//               `capflow run`)      events.jsonl (start, start_from, steady, fold, edit, pause,
//               continue, failure, branch_end, end)   run.log
// The first level from rest on NB > 8 is solved on NB=8 first and resampled (mesh sequencing:
// the long approach from the sphere at cheap evaluations). When the approach to a later level
// fails the health check, the branch has reached its resolution limit: it ends there, reported,
// with exit 0.
// A stop request (signal, or "run": {"state": "stopped"} saved in the control file) ends the
// branch at once: the level being solved is dropped, the states found are kept (exit 0).
// Live edits of the control file apply between states and approach steps, under capflow
// steady's policy (the schema's keys live for it: "ca" - a new list of levels replaces the
// levels beyond the last one solved; a continuation's to, step, after_fold and at -
// steady.solve_tolerance, time.tolerance and run.state: "paused" holds the run after the state
// being solved until "running" is saved); other keys are refused with a typed outcome
// (events.jsonl "edit", as in capflow run). start.from is refused inside the run's own
// directory, and its shape is rescaled to the reference volume as start.restore_volume says.
#pragma once

#include <atomic>
#include <optional>
#include <string>

#include "app/run_summary.h"
#include "control/options.h"

namespace capflow::app {

// The live control file: its path and its options as read (before command-line overrides,
// so that only keys saved with a new value count as edits).
struct SteadyControlFile {
  std::string path;
  control::ControlOptions options;
};

// UserError (exit 2): a rotational flow, a ramp, an occupied output directory. `stop`: set by
// a signal handler. `live`: the control file to watch (app/control_feed.h).
SteadySummary run_steady(const control::ControlOptions& options, bool overwrite,
                         const std::atomic<bool>* stop = nullptr,
                         const std::optional<SteadyControlFile>& live = std::nullopt);

}  // namespace capflow::app
