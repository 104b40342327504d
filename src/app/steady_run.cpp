// capflow/app/steady_run: see steady_run.h.
#include "app/steady_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <thread>
#include <vector>

#include "app/branch_follower.h"
#include "app/cpu_budget.h"
#include "app/errors.h"
#include "app/format.h"
#include "app/frames.h"
#include "app/level_solver.h"
#include "app/run_checkpoint.h"
#include "app/run_lifecycle.h"
#include "app/run_lines.h"
#include "app/steady_outputs.h"
#include "capsule/capsule.h"
#include "capsule/flow.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "control/edit.h"
#include "control/record.h"
#include "control/schedule.h"
#include "diagnostics/diagnostics.h"
#include "membrane/membrane.h"
#include "output/records.h"

namespace capflow::app {

namespace fs = std::filesystem;
using control::Record;

namespace {

// The levels of Ca the control file asks for (control/schedule.h), from Ca = 0.
std::vector<double> levels_of(const control::CaSchedule& s) {
  try {
    return control::schedule_levels(s, 0.0);
  } catch (const std::invalid_argument& e) {
    throw UserError(e.what());
  }
}

class SteadyRun {
 public:
  SteadyRun(const control::ControlOptions& o, bool overwrite,
            const std::optional<SteadyControlFile>& live, const std::atomic<bool>* signal)
      : opt_(o), file_opt_(live ? live->options : o) {
    if (!capsule::is_pure_straining(o.flow.gradient))
      throw UserError(
          "flow.type: capflow steady needs a pure straining flow (a symmetric flow.gradient: "
          "planar, uniaxial or biaxial extension). In " +
          o.flow.name() +
          " a steady capsule's membrane keeps moving (tank-treading), so its shape is not a "
          "root of the node velocities: use capflow run with \"steady\": {\"stop\": true}");
    levels_ = o.ca.continuation ? std::vector<double>{o.ca.continuation->from} : levels_of(o.ca);
    if (levels_.empty()) throw UserError("ca: no level to solve at");
    if (o.output.dir.empty()) throw UserError("output.dir: give a run directory (or -o DIR)");
    RunLifecycle::Spec spec;
    spec.command = control::Command::Steady;
    spec.timeseries_header = output::records::timeseries().header();
    spec.steady_header = output::records::steady_solve().header();
    spec.marches = false;
    life_ = RunLifecycle::create(NewRun{o, file_opt_, live ? live->path : "", overwrite}, spec,
                                 signal);
    try {
      std::string warning;
      set_solver_threads(opt_.numerics.threads, &warning);
      if (!warning.empty()) life_->warn("threads", warning, 0.0);
      fine_ = make_grid(o);
      if (life_->source())
        fine_.x = life_->start_shape(*fine_.mesh, fine_.cap->initial_volume(), opt_);
      solver_ = std::make_unique<LevelSolver>(opt_, fine_, hooks());
      out_ = std::make_unique<SteadyOutputs>(*life_, opt_, fine_);
    } catch (...) {
      life_->abandon();  // a start that failed leaves nothing behind
      throw;
    }
  }

  SteadySummary run() {
    SteadySummary sum;
    sum.continuation = opt_.ca.continuation.has_value();
    try {
      announce();
      life_->start_renderer(opt_, true);
      life_->begun();
      for (size_t i = 0; i < levels_.size(); ++i) {
        between_states();
        if (i >= levels_.size()) break;  // an edit ended the list here
        if (stopped()) {
          say("stopped before Ca = " + fixed(levels_[i], 6));
          sum.termination = SteadyTermination::Stopped;
          break;
        }
        if (!solve_level(levels_[i], &sum)) break;
        ++sum.states;
      }
      if (opt_.ca.continuation && sum.states == 1 && !stopped()) follow_branch(&sum);
      out_->finish_frames();
    } catch (const OutputError& e) {
      sum.output_failed = true;
      sum.failure = e.what();
      sum.termination = SteadyTermination::OutputFailed;
      // the steady states found are its checkpoints: nothing more to keep
      if (!life_->keep_after_output_failure(e, solver_->time(), {})) return sum;
    }
    sum.levels = opt_.ca.continuation ? 0 : static_cast<int>(levels_.size());
    sum.wall_s = life_->wall();
    sum.evaluations = evaluations_;
    life_->end(sum.BriefReport(), sum.end_event(), solver_->time());
    return sum;
  }

 private:
  bool stopped() const { return life_->feed().stopping(); }
  void say(const std::string& s) { life_->say(s); }
  void event(Record r) { life_->event(std::move(r), solver_ ? solver_->time() : 0.0); }

  LevelSolver::Hooks hooks() {
    LevelSolver::Hooks h;
    h.say = [this](const std::string& s) { say(s); };
    h.status = [this](const std::string& s) {
      // at most one progress line per second on a terminal, every 10 s into a log
      const double now = life_->wall();
      if (now - last_progress_ < (life_->log().tty() ? 1.0 : 10.0)) return;
      last_progress_ = now;
      life_->log().status(s);
    };
    h.event = [this](const Record& r) { event(r); };
    h.between_steps = [this] { apply_edits(); };
    h.stop = life_->feed().stop();
    return h;
  }

  // One level: solved (its state written), or the run's end (false: stopped, a failure, the
  // branch's resolution limit - *sum says which).
  bool solve_level(double ca, SteadySummary* sum) {
    const auto t_level = std::chrono::steady_clock::now();
    solving_level_ = true;
    const LevelSolver::Result r =
        solver_->solve(ca, out_->states() == 0 && opt_.start.from.empty());
    solving_level_ = false;
    evaluations_ += r.evaluations;
    if (stopped()) {
      say("stopped: Ca = " + fixed(ca, 6) + " not finished");
      sum->termination = SteadyTermination::Stopped;
      return false;
    }
    if (r.converged) {
      write_state(ca, r.solution, r.newton, r.krylov, r.evaluations, t_level);
      return true;
    }
    const std::string failure = "Ca = " + std::to_string(ca) + ": " + r.failure;
    say("failure: " + failure);
    event(Record().set("event", "failure").set("ca", ca).set("message", failure));
    if (r.approach_failed && sum->states > 0) {
      // The time steps themselves fail (runaway node-to-node oscillation, a Jacobian sign
      // change) where the branch was continued from a steady state: the mesh no longer
      // resolves the shape.
      sum->resolution_limit = true;
      sum->failure = failure;
      sum->termination = SteadyTermination::ResolutionLimit;
      say("the branch ends at its resolution limit (raise mesh.nb to go on): " + failure);
      return false;
    }
    sum->failed = true;
    sum->failure = failure;
    sum->termination = SteadyTermination::Failed;
    out_->keep_last_good_state(ca, solver_->steps());
    return false;
  }

  void write_state(double ca, const capsule::SteadySolution& sol, int newton, long krylov,
                   long evaluations, std::chrono::steady_clock::time_point began) {
    SteadyState st;
    st.ca = ca;
    st.solution = &sol;
    st.newton = newton;
    st.krylov = krylov;
    st.evaluations = evaluations;
    st.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    st.folds = folds_;
    st.t = solver_->time();
    st.steps = solver_->steps();
    out_->write(st);
  }

  // The branch of a continuation from the first state (app/branch_follower.h).
  void follow_branch(SteadySummary* sum) {
    const control::Continuation& c = *opt_.ca.continuation;
    branch_ = std::make_unique<BranchFollower>(*solver_, fine_, c);
    for (;;) {
      between_states();
      if (stopped()) {
        say("stopped: the branch ends at Ca = " + fixed(branch_->branch().last().ca, 6));
        sum->termination = SteadyTermination::Stopped;
        return;
      }
      const auto t_state = std::chrono::steady_clock::now();
      const BranchFollower::Step step = branch_->advance();
      evaluations_ += step.evaluations;
      if (stopped()) continue;
      if (step.status == BranchFollower::Status::Done) return;
      const capsule::ArclengthContinuation& b = branch_->branch();
      if (step.status == BranchFollower::Status::Stuck) {
        sum->resolution_limit = true;
        sum->failure = b.why();
        sum->termination = SteadyTermination::ResolutionLimit;
        say("the branch ends: " + b.why());
        event(Record().set("event", "branch_end").set("message", b.why()));
        return;
      }
      if (b.fold_found_now()) report_fold(*b.fold(), opt_.ca.continuation->after_fold, sum);
      write_state(b.last().ca, step.k.last, step.k.newton, step.k.krylov, step.evaluations,
                  t_state);
      ++sum->states;
    }
  }

  // ---- live edits ---------------------------------------------------------------------------

  // Between two states: the saved edits of the control file, and a pause until it is lifted.
  void between_states() {
    apply_edits();
    while (life_->paused(opt_, solver_->time()) && !stopped()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      apply_edits();
    }
    if (!stopped()) life_->paused(opt_, solver_->time());  // "continue", once
  }

  // capflow steady's policy: the schema's keys live for it; a "ca" this run cannot take refused.
  control::EditPolicy policy() const {
    control::EditPolicy p;
    p.command = control::Command::Steady;
    p.veto = [this](const control::OptionChange& c, const control::ControlOptions& merged) {
      return c.path == "ca" ? control::level_edit_problem(opt_.ca, merged.ca) : std::string();
    };
    return p;
  }

  void apply_edits() {
    while (std::optional<RunLifecycle::Edit> e =
               life_->next_edit(&opt_, &file_opt_, policy(), solver_ ? solver_->time() : 0.0)) {
      const std::string note = e->result.schedule_changed ? apply_range(opt_.ca) : "";
      life_->report_edit(*e, solver_ ? solver_->time() : 0.0, note.empty() ? "" : "ca: " + note);
    }
  }

  // An applied "ca": the levels still to come, or the continuation's range; what happens.
  std::string apply_range(const control::CaSchedule& ca) {
    if (ca.continuation) {
      if (branch_) branch_->set_range(*ca.continuation);
      std::ostringstream m;
      m << "the branch goes on towards Ca = " << ca.continuation->to << " (steps up to "
        << ca.continuation->step << ", " << ca.continuation->after_fold << " states after a fold)";
      return m.str();
    }
    // The levels beyond the last one solved (or the one being solved: an edit during its
    // approach).
    const size_t done =
        std::min<size_t>(levels_.size(), out_->states() + (solving_level_ ? 1 : 0));
    levels_ = control::levels_to_come(levels_, done, control::schedule_levels(ca, 0.0));
    std::ostringstream m;
    m << levels_.size() - done << " level" << (levels_.size() - done == 1 ? "" : "s") << " to go";
    return m.str();
  }

  // ---- what is written ----------------------------------------------------------------------

  void announce() {
    say(steady_banner(opt_, levels_, *fine_.cap, life_->dir().path().string()));
    event(Record().set("event", "start").set_json("control", control::to_json_text(opt_)));
  }

  void report_fold(const capsule::Fold& f, int after_fold, SteadySummary* sum) {
    if (!sum->fold_ca) sum->fold_ca = f.ca;
    ++folds_;
    std::ostringstream m;
    m << "fold at Ca = " << fixed(f.ca, 6) << " (after state " << f.after_state
      << "): the branch turns back in Ca there; "
      << (folds_ % 2 ? "the states past it are unstable (a time march leaves them)"
                     : "the states past it are stable again")
      << "; " << after_fold << " state" << (after_fold == 1 ? "" : "s")
      << " past the first fold in all";
    say(m.str());
    event(Record()
              .set("event", "fold")
              .set("ca", f.ca)
              .set("arclength", f.arclength)
              .set("folds", folds_));
  }

  control::ControlOptions opt_;
  control::ControlOptions file_opt_;  // the control file as last read (live edits)
  std::unique_ptr<RunLifecycle> life_;
  Grid fine_;  // the control file's mesh
  std::unique_ptr<LevelSolver> solver_;
  std::unique_ptr<BranchFollower> branch_;
  std::vector<double> levels_;
  std::unique_ptr<SteadyOutputs> out_;
  int folds_ = 0;               // folds the continuation passed
  bool solving_level_ = false;  // a level's approach and solve are under way
  long evaluations_ = 0;  // velocity evaluations of the levels done, on every grid
  double last_progress_ = -1e30;
};

}  // namespace

SteadySummary run_steady(const control::ControlOptions& options, bool overwrite,
                         const std::atomic<bool>* stop,
                         const std::optional<SteadyControlFile>& live) {
  SteadyRun r(options, overwrite, live, stop);
  return r.run();
}

}  // namespace capflow::app
