// capflow run CONTROL.json: simulate the capsule as the control file says (see README,
// "Control file"). Exit codes: 0 done, 2 invalid control file or arguments, 4 the simulation
// failed (the message names the cause, time and location; the last good state is kept).
#include <atomic>
#include <csignal>
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "app/simulation.h"
#include "control/control_file.h"

namespace capflow::app {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int sig) {
  if (g_stop.load()) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);  // second signal: exit at once
    return;
  }
  g_stop.store(true);
}

struct RunArgs {
  std::string control;
  std::string output_dir;
};

void run_cmd(const RunArgs& a) {
  control::ParsedControl parsed;
  try {
    parsed = control::load_control_file(a.control);
  } catch (const control::ControlError& e) {
    throw UserError(e.what());
  }
  if (!a.output_dir.empty()) parsed.options.output.dir = a.output_dir;
  for (const auto& w : parsed.warnings) std::cerr << "capflow: warning: " << w.str() << "\n";
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  Simulation sim(parsed.options);
  const RunSummary s = sim.run(&g_stop);
  if (s.failed) set_exit_code(4);
}

void setup_run(CLI::App& root) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* c = root.add_subcommand("run", "Simulate a capsule as the control file says");
  c->add_option("control", args->control, "Control file (JSON)")->required()->check(CLI::ExistingFile);
  c->add_option("-o,--output", args->output_dir, "Run directory (overrides output.dir)");
  c->callback([args] { run_cmd(*args); });
}

}  // namespace

CAPFLOW_COMMAND(5, setup_run);

}  // namespace capflow::app
