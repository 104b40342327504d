// capflow/app/sweep_args: see sweep_args.h.
#include "app/sweep_args.h"

#include "app/errors.h"

namespace capflow::app {

void add_sweep_args(CLI::App* c, SweepArgs* args) {
  c->add_option("sweep", args->file, "Sweep file (JSON: base, vary, output.dir)")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("--case", args->only_case, "Run this case only (a Slurm array task)")
      ->check(CLI::Range(0, 1000000));
  c->add_flag("--slurm", args->slurm,
              "Write the case files and a Slurm job array (sweep.sbatch); run nothing");
  c->add_option("-j,--jobs", args->jobs,
                "Cases run side by side, each with cores / jobs OpenMP threads (default 1)")
      ->check(CLI::Range(1, 1024));
  c->add_flag("--summary", args->summary, "Rewrite sweep.csv from the case directories only");
  c->add_flag("--overwrite", args->overwrite,
              "Start the sweep in output.dir afresh (its cases are removed), or write it into a "
              "directory that holds other files (none of them is removed)");
  c->add_option("--ranks-per-case", args->ranks_per_case,
                "Under mpirun -np N (N a multiple of G): each case runs on a group of G ranks, "
                "N / G cases side by side (default 1: one case per rank, no MPI)")
      ->check(CLI::Range(1, 100000));
}

void check_sweep_args(const SweepArgs& a, int launched) {
  if (a.slurm && a.summary) throw UserError("--slurm and --summary: give one of them");
  if (a.ranks_per_case > 1) {
    if (a.jobs > 1) throw UserError("--ranks-per-case and --jobs: give one of them");
    if (a.slurm || a.summary || a.only_case >= 0)
      throw UserError(
          "--ranks-per-case runs the sweep under mpirun; not with --slurm, --summary "
          "or --case");
  }
  if (a.overwrite && (a.ranks_per_case > 1 || launched > 1 || a.only_case >= 0 || a.summary))
    throw UserError(
        "--overwrite starts the sweep afresh: give it to one process (not under mpirun, srun or a "
        "Slurm array task, not with --summary), then run the sweep's ranks without it");
}

}  // namespace capflow::app
