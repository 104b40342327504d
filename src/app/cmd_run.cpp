// capflow run CONTROL.json | --resume RUN_DIR: simulate the capsule as the control file says (see
// docs/usage.md, "capflow run"); the control file is watched and edits steer the run.
// Signals: the first SIGINT/SIGTERM/SIGHUP finishes the current step, writes a checkpoint,
// finalises the movie and exits with a summary; a second one exits at once (the fragmented MP4
// stays playable). SIGXFSZ is ignored, so that a file-size limit is an output failure (exit 5)
// rather than a kill.
// Exit codes (app/errors.h): 0 done, 2 invalid input, 3 internal error, 4 the simulation
// failed, 5 a run file could not be written.
#include <atomic>
#include <csignal>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/simulation.h"
#include "app/stop_signal.h"
#include "control/control_file.h"

namespace capflow::app {
namespace {

struct RunArgs {
  std::string control;
  std::string output_dir;
  std::string resume;
  bool overwrite = false;
  double t_end = -1;
};

std::unique_ptr<Simulation> resume_run(const RunArgs& a) {
  if (!a.control.empty() || !a.output_dir.empty() || a.overwrite)
    throw UserError(
        "--resume RUN_DIR takes no control file, --output or --overwrite: the run "
        "directory holds its control (edit its watched control file to steer)");
  ResumeOverrides ov;
  if (a.t_end > 0) ov.t_end = a.t_end;
  try {
    return Simulation::resume(a.resume, ov);
  } catch (const UserError& e) {
    throw UserError(std::string("cannot resume: ") + e.what());
  }
}

std::unique_ptr<Simulation> new_run(const RunArgs& a) {
  if (a.control.empty())
    throw UserError("give a control file (capflow run CONTROL.json) or --resume RUN_DIR");
  control::ParsedControl parsed;
  try {
    parsed = control::load_control_file(a.control);
  } catch (const control::ControlError& e) {
    throw UserError(e.what());
  }
  NewRun run{parsed.options, parsed.options, a.control, a.overwrite};
  if (!a.output_dir.empty()) run.options.output.dir = a.output_dir;
  if (a.t_end > 0) {
    run.options.time.t_end = a.t_end;
    const auto issues = control::time_issues(run.options.time, 0.0);
    if (!issues.empty())
      throw UserError("--t-end " + std::to_string(a.t_end) + ": " + issues[0].message);
  }
  for (const auto& w : parsed.warnings) std::cerr << "capflow: warning: " << w.str() << "\n";
  return std::make_unique<Simulation>(run);
}

void run_cmd(const RunArgs& a) {
  std::signal(SIGXFSZ, SIG_IGN);
  std::unique_ptr<Simulation> sim = a.resume.empty() ? new_run(a) : resume_run(a);
  const RunSummary s = sim->run(install_stop_signals());
  set_exit_code(s.exit_code());
}

void setup_run(CLI::App& root) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* c = root.add_subcommand("run", "Simulate a capsule as the control file says");
  c->add_option("control", args->control, "Control file (JSON); watched for live edits")
      ->check(CLI::ExistingFile);
  c->add_option("-o,--output", args->output_dir, "Run directory (overrides output.dir)");
  c->add_flag("--overwrite", args->overwrite,
              "Replace the capflow run already in the run directory (its files are removed)");
  c->add_option("--resume", args->resume, "Continue the run in RUN_DIR from its newest checkpoint")
      ->check(CLI::ExistingDirectory);
  // The same range as time.t_end in the control file.
  const CLI::Validator t_end_range(
      [](std::string& v) -> std::string {
        try {
          size_t used = 0;
          const double t = std::stod(v, &used);
          if (used == v.size() && t > 0.0 && t <= 1e6) return "";
        } catch (const std::exception&) {
        }
        return "--t-end " + v + " is not valid: give a simulated end time in (0, 1e6]";
      },
      "in (0, 1e6]");
  c->add_option("--t-end", args->t_end, "End time (overrides time.t_end; with --resume: extend)")
      ->check(t_end_range);
  c->callback([args] { run_cmd(*args); });
}

}  // namespace

CAPFLOW_COMMAND(5, setup_run);

}  // namespace capflow::app
