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
  add_sweep_args(c, args.get());
  c->callback([args] { set_exit_code(run_sweep(*args)); });
}

}  // namespace

CAPFLOW_COMMAND(7, setup_sweep);

}  // namespace capflow::app
