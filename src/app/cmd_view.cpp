// capflow view RUN_DIR [--serve [ADDR:]PORT]: the live console (app/live_console.h) for a run
// directory - the recorded history of a finished run, and for a run still going on (another
// process holds its lock) its live data too, steering through the run's control file
// (control.source). Serves until SIGINT or SIGTERM.
// Exit codes (app/errors.h): 0 after a signal, 2 not a run directory or a bad address.
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/console_source.h"
#include "app/errors.h"
#include "app/live_console.h"
#include "app/stop_signal.h"

namespace capflow::app {
namespace {

struct ViewArgs {
  std::string dir;
  ServeOptions serve{"0", 0};
};

int view(const ViewArgs& a) {
  try {
    const std::atomic<bool>* stop = install_stop_signals();
    RunDirectorySource source(a.dir);
    LiveConsole console(source, a.serve);
    console.linger(stop);  // until a signal
    return 0;
  } catch (const std::exception& e) {
    return report_failure(e);
  }
}

void setup_view(CLI::App& root) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* c = root.add_subcommand(
      "view", "Watch a run directory in the browser: its history, and live data while it runs");
  c->add_option("run_dir", args->dir, "Run directory")->required()->check(CLI::ExistingDirectory);
  add_serve_options(c, &args->serve, /*linger=*/false);
  c->callback([args] {
    args->serve.linger = 1e9;  // until a signal
    set_exit_code(view(*args));
  });
}

}  // namespace

CAPFLOW_COMMAND(9, setup_view);

}  // namespace capflow::app
