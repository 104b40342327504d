// capflow sweep SWEEP.json: one run per combination of the values a sweep file lists
// (app/sweep.h, control/sweep.h; docs/usage.md, "capflow sweep").
#include <memory>

#include "app/commands.h"
#include "app/sweep.h"

namespace capflow::app {
namespace {

void setup_sweep(CLI::App& root) {
  auto args = std::make_shared<SweepArgs>();
  CLI::App* c = root.add_subcommand(
      "sweep",
      "Run a sweep: one run directory per combination of the values a sweep file lists, and a "
      "summary sweep.csv; re-running it finishes what is missing");
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
  c->callback([args] { set_exit_code(run_sweep(*args)); });
}

}  // namespace

CAPFLOW_COMMAND(7, setup_sweep);

}  // namespace capflow::app
