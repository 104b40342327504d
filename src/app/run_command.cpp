// capflow/app/run_command: see run_command.h.
#include "app/run_command.h"

#include <csignal>
#include <memory>

#include "app/console.h"
#include "app/console_source.h"
#include "app/errors.h"
#include "app/simulation.h"
#include "app/stop_signal.h"
#include "control/control_file.h"
#include "membrane/law.h"

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

NewRun new_run_spec(const RunArgs& a) {
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
  return run;
}

std::unique_ptr<RunFeed> make_feed(const std::string& dir, const control::ControlOptions& o,
                                   const std::string& control_source) {
  return std::make_unique<RunFeed>(dir, control_source, control::Command::Run, o.render,
                                   membrane::to_string(o.law.kind));
}

}  // namespace

int run_command(const RunArgs& a) {
  try {
    std::signal(SIGXFSZ, SIG_IGN);
    const std::atomic<bool>* stop = install_stop_signals();
    std::unique_ptr<Simulation> sim;
    std::unique_ptr<RunFeed> feed;
    std::unique_ptr<LiveConsole> live;
    if (a.resume.empty()) {
      const NewRun run = new_run_spec(a);
      // The console first: an address that cannot be bound refuses the run before it starts.
      if (a.serve.enabled()) {
        feed = make_feed(run.options.output.dir, run.options, run.control_source);
        live = std::make_unique<LiveConsole>(*feed, a.serve);
      }
      sim = std::make_unique<Simulation>(run);
    } else {
      sim = resume_run(a);
      if (a.serve.enabled()) {
        feed = make_feed(a.resume, sim->options(), sim->lifecycle().control_source());
        live = std::make_unique<LiveConsole>(*feed, a.serve);
      }
    }
    if (feed) {
      sim->outputs().add_observer([f = feed.get()](const StateRecord& s) { f->observe(s); });
      const std::string url = live->url();
      sim->lifecycle().say("console at " + url.substr(0, url.find("?token")) +
                           " (its token is on the terminal)");
    }
    const int code = sim->run(stop).exit_code();
    if (live) live->linger(stop);
    return code;
  } catch (const std::exception& e) {
    return report_failure(e);
  }
}

}  // namespace capflow::app
