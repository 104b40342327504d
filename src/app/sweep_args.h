// capflow/app/sweep_args: the command line of `capflow sweep` - its options, and the checks of
// how they combine before the sweep file is read (so that a bad option exits 2 naming it, and the
// option fuzzer can run the same checks: tests/fuzz/fuzz_options.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace capflow::app {

struct SweepArgs {
  std::string file;        // the sweep file
  int only_case = -1;      // >= 0: run this case only, leave sweep.csv alone (Slurm array tasks)
  bool slurm = false;      // write the case files and sweep.sbatch, run nothing
  bool summary = false;    // rewrite sweep.csv from the case directories, run nothing
  int jobs = 1;            // cases side by side (each with cores / jobs OpenMP threads)
  int ranks_per_case = 1;  // > 1: under an MPI launcher, each case runs on a group of this many
  bool overwrite = false;  // start an existing sweep afresh; allow a non-empty directory
};

void add_sweep_args(CLI::App* sub, SweepArgs* a);

// Options that do not go together (UserError naming them). `launched`: the processes an MPI
// launcher started (1 when none).
void check_sweep_args(const SweepArgs& a, int launched);

}  // namespace capflow::app
