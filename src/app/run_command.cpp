// capflow/app/run_command: see run_command.h.
#include "app/run_command.h"

#include <csignal>
#include <memory>

#include "app/console.h"
#include "app/errors.h"
#include "app/simulation.h"
#include "app/stop_signal.h"
#include "control/control_file.h"

namespace capflow::app {
namespace {

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
  control::ParsedControl parsed = control::load_control_file(a.control);  // exit 2 when bad
  NewRun run{parsed.options, parsed.options, a.control, a.overwrite};
  if (!a.output_dir.empty()) run.options.output.dir = a.output_dir;
  if (a.t_end > 0) {
    run.options.time.t_end = a.t_end;
    const auto issues = control::time_issues(run.options.time, 0.0);
    if (!issues.empty())
      throw UserError("--t-end " + std::to_string(a.t_end) + ": " + issues[0].message);
  }
  for (const auto& w : parsed.warnings) console::err("capflow: warning: " + w.str());
  return std::make_unique<Simulation>(run);
}

}  // namespace

int run_command(const RunArgs& a) {
  try {
    std::signal(SIGXFSZ, SIG_IGN);
    std::unique_ptr<Simulation> sim = a.resume.empty() ? new_run(a) : resume_run(a);
    return sim->run(install_stop_signals()).exit_code();
  } catch (const std::exception& e) {
    return report_failure(e);
  }
}

}  // namespace capflow::app
