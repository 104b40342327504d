// capflow/app/worker_team: the ranks of an MPI run (parallel/team.h) sharing the velocity.
//
// Rank 0 runs the command as always: the control file and its watcher, the run directory, the
// renderer and every output are its alone. The other ranks serve it. For each capsule rank 0
// builds, it announces the effective control (control::to_json_text), from which every rank
// builds the same mesh and operators. At every velocity evaluation the single-layer targets are
// dealt out to the ranks in turn (every N-th target), each rank sums its share, and rank 0
// gathers them.
// A target's sum is the same code on the same data whichever rank makes it, so a run is bit for
// bit the same for any number of ranks, and its checkpoints resume with any other number. Edits,
// pauses, stops, checkpoint requests and signals are rank 0's: the other ranks ignore SIGINT,
// SIGTERM and SIGHUP and end when rank 0 ends them (end_workers, on every way out of main). A
// failure on a serving rank ends every rank (parallel::abort_all).
// At lambda != 1 the double-layer matrix of the viscosity-ratio solve is assembled the same way:
// each rank makes the rows of its share of the targets, rank 0 gathers them and runs GMRES on
// the matrix (a product with a 3 targets x 3 targets matrix per iteration: ~0.1 % of the
// assembly, not worth spreading).
#pragma once

#include "capsule/capsule.h"
#include "control/options.h"

namespace capflow::app {

// Rank 0: lets `cap`, built from `options`, take its single layer from every rank (nothing for a
// team of one). The capsule must outlive its use.
void attach_team(capsule::Capsule& cap, const control::ControlOptions& options);

// Rank 0: the other ranks drop the capsules built so far (a sweep's group between its cases:
// the next case builds its own; nothing for a team of one).
void reset_workers();

// Rank 0: ends the other ranks' service (once; nothing for a team of one).
void end_workers();

// Ranks > 0: serves rank 0 until it ends the service; returns the exit code.
int serve_team();

}  // namespace capflow::app
