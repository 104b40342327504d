// capflow steady CONTROL.json [-o DIR] [--overwrite]: steady shapes found directly as roots of
// the node velocities, level by level of Ca (app/steady_run.h; docs/usage.md, "capflow steady").
// Signals: SIGINT/SIGTERM/SIGHUP end the branch at once (the states found are kept), as does
// "run": {"state": "stopped"} saved in the control file, which is watched for live edits.
// Exit codes (app/errors.h): 0 every level solved, 2 invalid input (a rotational flow, a ramp),
// 4 a level without a steady state, 5 a run file could not be written.
#include <atomic>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/console.h"
#include "app/console_source.h"
#include "app/live_console.h"
#include "app/steady_run.h"
#include "app/stop_signal.h"
#include "control/control_file.h"

namespace capflow::app {
namespace {

struct SteadyArgs {
  std::string control;
  std::string output_dir;
  bool overwrite = false;
  ServeOptions serve;
};

void steady_cmd(const SteadyArgs& a) {
  control::ParsedControl parsed = control::load_control_file(a.control);  // exit 2 when bad
  const SteadyControlFile live{a.control, parsed.options};
  if (!a.output_dir.empty()) parsed.options.output.dir = a.output_dir;
  for (const auto& w : parsed.warnings)
    if (w.path != "time.dt") console::err("capflow: warning: " + w.str());
  const std::atomic<bool>* stop = install_stop_signals();
  // The console shows the run directory as the solver fills it (states at each level).
  std::unique_ptr<RunDirectorySource> source;
  std::unique_ptr<LiveConsole> console;
  if (a.serve.enabled()) {
    source = std::make_unique<RunDirectorySource>(parsed.options.output.dir, a.control,
                                                  control::Command::Steady,
                                                  parsed.options.render);
    console = std::make_unique<LiveConsole>(*source, a.serve);
  }
  const SteadySummary s = run_steady(parsed.options, a.overwrite, stop, live);
  if (console) console->linger(stop);
  set_exit_code(s.exit_code());
}

void setup_steady(CLI::App& root) {
  auto args = std::make_shared<SteadyArgs>();
  CLI::App* c = root.add_subcommand(
      "steady", "Find the steady shapes at the control file's levels of Ca (pure straining flows)");
  c->add_option("control", args->control, "Control file (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("-o,--output", args->output_dir, "Run directory (overrides output.dir)");
  c->add_flag("--overwrite", args->overwrite,
              "Replace the capflow run already in the run directory (its files are removed)");
  add_serve_options(c, &args->serve);
  c->callback([args] { steady_cmd(*args); });
}

}  // namespace

CAPFLOW_COMMAND(6, setup_steady);

}  // namespace capflow::app
