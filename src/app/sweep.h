// capflow/app/sweep: `capflow sweep SWEEP.json` - one run per case of a sweep file
// (control/sweep.h), each a `capflow run` child process, and a summary.
//
// Sweep directory (output.dir of the sweep file):
//   case_NNN.json   the case's control file (written once; a later sweep whose case differs is
//                   refused: the runs would not belong to it)
//   case_NNN/       the case's run directory          case_NNN.log  its console output
//   sweep.csv       one row per case: its values, status, exit code, end reason and final
//                   t, D, L, S, W, steps (rewritten after every case)
//   sweep.sbatch    with --slurm: a Slurm job array, one task per case (--case
//   $SLURM_ARRAY_TASK_ID)
// A case's status comes from its run directory (the run's "end" event, control/run_events.h):
//   done         ended with exit code 0 (t_end, steady state, run.state "stopped"): skipped
//   failed       the simulation failed (exit 4): skipped, reported (remove case_NNN/ to retry)
//   interrupted  stopped by a signal, an output failure, or no end at all: resumed from its
//                newest checkpoint (restarted when it has none)
//   new          no run yet: started
// So re-running a sweep finishes what is missing and does nothing once every case is done.
// Under an MPI launcher (`mpirun -np R capflow sweep ...`, or srun) each of the R processes runs
// the cases with index % R == its rank (the rank from the launcher's environment; the cases do
// not communicate); each rewrites sweep.csv after its cases, so the last one to finish leaves
// the complete summary. With --ranks-per-case G the R ranks (R a multiple of G) start MPI and
// form R / G groups of G consecutive ranks (parallel::split); group g runs the cases with
// index % (R / G) == g one after another, each in the group's processes as `capflow run` runs
// under mpirun (app/run_command.h, app/worker_team.h: the group's first rank drives the run, its
// console output appended to case_NNN.log; the others share its velocity evaluations), so a
// case's results are those of a run on G ranks, bit for bit those of one process. --jobs N runs N
// cases side by side, each with (cores / N) OpenMP threads unless OMP_NUM_THREADS is set. Each
// child runs in its own process group: the first SIGINT/SIGTERM/SIGHUP of the sweep is passed to
// the running cases as one SIGTERM each (they checkpoint and stop), and no further case starts.
// The sweep directory follows run's rules: new, empty, or a sweep of capflow's (continued); a
// directory with anything else is refused unless --overwrite, which writes the sweep beside what
// is there but never replaces a file capflow did not write (a user's sweep.csv is refused);
// --overwrite on a sweep removes its own entries and starts it afresh.
// Only `capflow run` controls are swept (not `capflow steady` ones).
#pragma once

#include <string>

#include "app/sweep_args.h"

namespace capflow::app {

// Runs the sweep; returns the exit code (0 every case done, 4 some case failed, 5 an output
// failure). UserError for a bad sweep file or arguments (exit 2).
int run_sweep(const SweepArgs& args);

}  // namespace capflow::app
