// capflow run CONTROL.json | --resume RUN_DIR: simulate the capsule as the control file says (see
// docs/usage.md, "capflow run"); the control file is watched and edits steer the run.
// Signals: the first SIGINT/SIGTERM/SIGHUP finishes the current step, writes a checkpoint,
// finalises the movie and exits with a summary; a second SIGINT or SIGTERM exits at once (the
// fragmented MP4 stays playable). SIGPIPE is ignored: a closed console does not stop a run. SIGXFSZ is ignored, so that a file-size limit is an output failure (exit 5)
// rather than a kill.
// Exit codes (app/errors.h): 0 done, 2 invalid input, 3 internal error, 4 the simulation
// failed, 5 a run file could not be written.
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/run_command.h"

namespace capflow::app {
namespace {

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
  add_serve_options(c, &args->serve);
  c->callback([args] { set_exit_code(run_command(*args)); });
}

}  // namespace

CAPFLOW_COMMAND(5, setup_run);

}  // namespace capflow::app
