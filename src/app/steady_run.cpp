#include "app/steady_run.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <sstream>
#include <thread>
#include <vector>

#include "app/errors.h"
#include "app/frames.h"
#include "app/run_checkpoint.h"
#include "app/run_directory.h"
#include "app/run_log.h"
#include "app/steady_control.h"
#include "app/time_stepper.h"
#include "app/worker_team.h"
#include "capsule/capsule.h"
#include "capsule/continuation.h"
#include "capsule/health.h"
#include "capsule/steady_solver.h"
#include "control/control_file.h"
#include "control/edit.h"
#include "control/record.h"
#include "control/schedule.h"
#include "diagnostics/diagnostics.h"
#include "geometry/surface.h"
#include "membrane/membrane.h"

namespace capflow::app {

namespace fs = std::filesystem;
using control::Record;

int SteadySummary::exit_code() const {
  return outcome_exit_code(failed, output_failed);
}

namespace {

constexpr double kApproachSpeed = 2e-2;   // largest node speed (a G) that ends the approach
constexpr double kMapStepFactor = 0.5;    // midpoint map step / adaptive (Cash-Karp) steps
constexpr double kMaxApproachTime = 400;  // simulated time the approach may take per level
constexpr int kSolveAttempts = 3;
constexpr int kMinApproachSteps = 10;  // for the controller to reach the stability limit
constexpr int kCoarseNb = 8;           // the first level is solved on NB=8 first
// The climb (SteadyRun::climb): the start's Ca is lowered by kClimbFactor at a time, at most
// kClimbTries times, until the NB=8 state resolves its tips; the branch from there has
// kClimbStates states at least.
constexpr double kClimbFactor = 0.75;
constexpr int kClimbTries = 4;
constexpr int kClimbStates = 4;

const char* const kTimeseriesHeader =
    "t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,inclination_deg,"
    "volume_drift,steps,dt,wall_s\n";
const char* const kSteadyHeader =
    "t,ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min,residual,speed,volume_drift,"
    "newton,krylov,evaluations,wall_s,folds\n";

// The levels of Ca the control file asks for (control/schedule.h), from Ca = 0.
std::vector<double> levels_of(const control::CaSchedule& s) {
  try {
    return control::schedule_levels(s, 0.0);
  } catch (const std::invalid_argument& e) {
    throw UserError(e.what());
  }
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::string scientific(double v) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(2) << v;
  return s.str();
}

// A mesh, its capsule and the state on it.
struct Grid {
  std::unique_ptr<geometry::Mesh> mesh;
  std::unique_ptr<capsule::Capsule> cap;
  Eigen::Matrix3Xd x;
  double h_last = 0;  // the last adaptive step size measured on this grid
};

Grid make_grid(const control::ControlOptions& o) {
  Grid g;
  g.mesh = control::make_mesh(o.mesh);
  g.cap = std::make_unique<capsule::Capsule>(*g.mesh, o.law, o.flow, control::dynamics_options(o));
  attach_team(*g.cap, o);  // the ranks of an MPI run share its velocity evaluations
  g.x = g.cap->positions();
  return g;
}

class SteadyRun {
 public:
  SteadyRun(const control::ControlOptions& o, bool overwrite,
            const std::optional<SteadyControlFile>& live)
      : opt_(o), file_opt_(live ? live->options : o), control_path_(live ? live->path : "") {
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
    dir_ = RunDirectory::open(
        o.output.dir, overwrite ? RunDirectory::Mode::Overwrite : RunDirectory::Mode::Create);
    try {
      dir_->open_records(true, kTimeseriesHeader, kSteadyHeader);
      log_ = std::make_unique<RunLog>(*dir_, isatty(STDERR_FILENO));
      dir_->write_text("control.json", control::to_json_text(opt_));
      fine_ = make_grid(o);
      if (!o.start.from.empty()) start_from();
    } catch (...) {
      // A start that failed leaves nothing behind: the same command works once the cause is gone.
      log_.reset();
      dir_->abandon();
      throw;
    }
  }

  SteadySummary run(const std::atomic<bool>* signal) {
    control_ = std::make_unique<SteadyControl>(control_path_, signal);
    SteadySummary sum;
    announce();
    renderer_ = start_renderer(opt_, *dir_, "movie.mp4", true,
                               [this](const std::string& line) { say(line); });
    for (size_t i = 0; i < levels_.size(); ++i) {
      between_states();
      if (i >= levels_.size()) break;  // an edit ended the list here
      if (stopped()) {
        say("stopped before Ca = " + fixed(levels_[i], 6));
        break;
      }
      const bool ok = solve_level(levels_[i]);
      if (!ok && stopped()) {
        say("stopped: Ca = " + fixed(levels_[i], 6) + " not finished");
        break;
      }
      if (!ok && approach_failed_ && sum.states > 0) {
        // The time steps themselves fail (runaway node-to-node oscillation, a Jacobian sign
        // change) where the branch was continued from a steady state: the mesh no longer
        // resolves the shape.
        sum.resolution_limit = true;
        sum.failure = failure_;
        say("the branch ends at its resolution limit (raise mesh.nb to go on): " + failure_);
        break;
      }
      if (!ok) {
        sum.failed = true;
        sum.failure = failure_;
        keep_last_good_state(levels_[i]);
        break;
      }
      ++sum.states;
    }
    if (opt_.ca.continuation && sum.states == 1 && !stopped()) follow_branch(&sum);
    finish_frames(&sum);
    sum.wall_s = wall();
    sum.evaluations = evaluations_;
    std::ostringstream m;
    m << "end: " << sum.states << " steady state" << (sum.states == 1 ? "" : "s");
    if (opt_.ca.continuation)
      m << " on the branch" << (sum.fold_ca ? ", fold at Ca = " + fixed(*sum.fold_ca, 6) : "");
    else
      m << " of " << levels_.size();
    m << ", " << sum.evaluations << " velocity evaluations, wall " << fixed(sum.wall_s, 1) << " s"
      << (sum.failed ? " (" + sum.failure + ")" : "");
    say(m.str());
    Record end = Record()
                     .set("event", "end")
                     .set("states", sum.states)
                     .set("resolution_limit", sum.resolution_limit)
                     .set("exit_code", sum.exit_code())
                     .set("velocity_evaluations", sum.evaluations)
                     .set("wall_s", sum.wall_s);
    if (sum.fold_ca) end.set("fold_ca", *sum.fold_ca);
    log_->event(end, t_);
    return sum;
  }

 private:
  bool stopped() const { return control_->stopping(); }

  // One frame per steady state (output.png, output.mp4; app/frames.h); the preview
  // (render.preview) shows the last state.
  void submit_frame(double ca, const diagnostics::ShapeDiagnostics& d,
                    const membrane::MembraneFields& f) {
    if (!renderer_) return;
    render::Snapshot sn =
        state_snapshot(*fine_.cap, fine_.x, t_, ca, membrane::to_string(opt_.law.kind),
                       {d.D, d.L, d.S, d.W, f.tension1.maxCoeff(), f.tension2.minCoeff()});
    if (opt_.render.preview) renderer_->offer_preview(sn);
    if (!frames_wanted()) return;
    sn.frame = frames_++;
    if (!renderer_->submit_frame(std::move(sn)))
      throw OutputError("frames could not be written: " + renderer_->error());
  }

  bool frames_wanted() const { return opt_.output.png || opt_.output.mp4.enabled; }

  void finish_frames(SteadySummary* sum) {
    if (!renderer_) return;
    const render::RenderStats rs = renderer_->stop();
    const std::string err = renderer_->error();
    renderer_.reset();
    if (!err.empty()) {
      sum->output_failed = true;
      say("frames could not be written: " + err);
      return;
    }
    if (frames_wanted())
      say("renderer: " + std::to_string(frames_) + " frame" + (frames_ == 1 ? "" : "s") +
          " written, one per steady state" +
          (opt_.output.mp4.enabled ? " (" + std::to_string(rs.movie_frames) + " in the movie)"
                                   : std::string()));
  }

  // Between two states: the saved edits of the control file, and a pause until it is lifted.
  void between_states() {
    apply_edits();
    if (opt_.run.state != control::RunState::Paused) return;
    say("paused (run.state \"paused\"): save \"running\" to go on");
    log_->event(Record().set("event", "paused"), t_);
    while (opt_.run.state == control::RunState::Paused && !stopped()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      apply_edits();
    }
    if (!stopped()) {
      say("resumed");
      log_->event(Record().set("event", "resumed"), t_);
    }
  }

  // The saved versions of the control file since the last call (SteadyControl): applied when
  // capflow steady uses the key (kSteadyLiveKeys), refused otherwise.
  void apply_edits() {
    while (std::optional<SteadyControl::Saved> saved = control_->take()) {
      if (!saved->parsed) {
        say("refused edit of " + control_path_ + " (the run keeps its settings):\n  " +
            saved->error);
        log_->event(Record()
                        .set("event", "edit")
                        .set("accepted", false)
                        .set("errors", std::vector<std::string>{saved->error}),
                    t_);
        continue;
      }
      control::EditResult r = control::apply_edit(opt_, file_opt_, saved->parsed->options);
      file_opt_ = saved->parsed->options;
      keep_steady_keys(&r);
      if (r.applied.empty() && r.refused.empty()) continue;
      std::string ca_note;
      if (r.schedule_changed) ca_note = edit_range(r.merged.ca);
      opt_ = r.merged;
      if (!ca_note.empty() && ca_note.rfind("refused", 0) == 0) opt_.ca = previous_ca_;
      report_edit(r, ca_note);
    }
  }

  // Moves the applied changes of keys capflow steady does not use to the refused ones.
  void keep_steady_keys(control::EditResult* r) const {
    static const char* const kSteadyLiveKeys[] = {"ca", "steady.solve_tolerance", "time.tolerance",
                                                  "run.state"};
    control::ControlOptions merged = opt_;
    std::vector<control::OptionChange> applied;
    for (control::OptionChange& c : r->applied) {
      if (std::find(std::begin(kSteadyLiveKeys), std::end(kSteadyLiveKeys), c.path) !=
          std::end(kSteadyLiveKeys)) {
        applied.push_back(c);
        continue;
      }
      c.reason = "capflow steady does not use it";
      r->refused.push_back(c);
    }
    for (const control::OptionChange& c : applied) {
      if (c.path == "ca") merged.ca = r->merged.ca;
      if (c.path == "steady.solve_tolerance")
        merged.steady.solve_tolerance = r->merged.steady.solve_tolerance;
      if (c.path == "time.tolerance") merged.time.tolerance = r->merged.time.tolerance;
      if (c.path == "run.state") merged.run.state = r->merged.run.state;
    }
    r->applied = applied;
    r->merged = merged;
  }

  // A new "ca": the levels still to come, or the continuation's range. Returns what happens
  // ("refused: ..." when the edit cannot apply to this run).
  std::string edit_range(const control::CaSchedule& ca) {
    previous_ca_ = opt_.ca;
    const bool was_branch = opt_.ca.continuation.has_value();
    if (was_branch != ca.continuation.has_value())
      return std::string("refused: this run ") +
             (was_branch ? "follows a continuation: edit its to, step or after_fold"
                         : "solves at levels: give levels (a continuation starts a new run)");
    if (was_branch) {
      if (ca.continuation->from != opt_.ca.continuation->from)
        return "refused: continuation.from cannot change once the branch has started (to, step "
               "and after_fold can)";
      if (branch_)
        branch_->set_range(ca.continuation->to, ca.continuation->step, ca.continuation->after_fold,
                           ca.continuation->at);
      std::ostringstream m;
      m << "the branch goes on towards Ca = " << ca.continuation->to << " (steps up to "
        << ca.continuation->step << ", " << ca.continuation->after_fold << " states after a fold)";
      return m.str();
    }
    std::vector<double> next;
    try {
      next = levels_of(ca);
    } catch (const UserError& e) {
      return std::string("refused: ") + e.what();
    }
    // The levels beyond the last one solved (or the one being solved: an edit during its
    // approach), in the direction the list moves.
    const size_t done = std::min<size_t>(levels_.size(), states_ + (solving_level_ ? 1 : 0));
    const bool any = done > 0;
    const double last = any ? levels_[done - 1] : 0.0;
    const double dir = next.size() > 1 && next.back() < next.front() ? -1.0 : 1.0;
    std::vector<double> kept(levels_.begin(), levels_.begin() + done);
    for (double v : next)
      if (!any || (v - last) * dir > 0) kept.push_back(v);
    levels_ = kept;
    std::ostringstream m;
    m << levels_.size() - done << " level" << (levels_.size() - done == 1 ? "" : "s") << " to go";
    return m.str();
  }

  void report_edit(const control::EditResult& r, const std::string& ca_note) {
    std::ostringstream m;
    m << "edit applied:";
    Record applied, refused;
    for (const auto& c : r.applied) {
      if (c.path == "ca" && ca_note.rfind("refused", 0) == 0) {
        m << " refused ca (" << ca_note.substr(9) << ");";
        refused.set(c.path, control::change_record(c, ca_note.substr(9)));
        continue;
      }
      m << " " << c.path << " " << c.old_value << " -> " << c.new_value
        << (c.path == "ca" ? " (" + ca_note + ")" : "") << ";";
      applied.set(c.path, control::change_record(c));
    }
    for (const auto& c : r.refused) {
      m << " refused " << c.path << " (" << c.reason << ");";
      refused.set(c.path, control::change_record(c, c.reason));
    }
    say(m.str());
    log_->event(Record()
                    .set("event", "edit")
                    .set("accepted", true)
                    .set("applied", applied)
                    .set("refused", refused),
                t_);
  }

  double wall() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  void say(const std::string& s) { log_->say(s); }
  // At most one progress line per second on a terminal, every 10 s into a log.
  bool progress_due() {
    const double now = wall();
    if (now - last_progress_ < (log_->tty() ? 1.0 : 10.0)) return false;
    last_progress_ = now;
    return true;
  }

  void announce() {
    std::ostringstream m;
    m << "capflow steady: " << membrane::to_string(opt_.law.kind) << ", " << opt_.flow.name()
      << ", NE=" << opt_.mesh.elements << " NB=" << opt_.mesh.nb << ", ";
    if (const auto& c = opt_.ca.continuation)
      m << "the branch from Ca = " << c->from << " towards " << c->to << " (steps up to " << c->step
        << ")";
    else
      m << levels_.size() << " level" << (levels_.size() == 1 ? "" : "s") << " of Ca from "
        << levels_.front() << " to " << levels_.back();
    m << ", symmetry targets " << fine_.cap->symmetry().targets().size() << " -> "
      << dir_->path().string();
    say(m.str());
    log_->event(Record().set("event", "start").set_json("control", control::to_json_text(opt_)),
                t_);
  }

  void start_from() {
    const RunCheckpoint src = read_latest_checkpoint(opt_.start.from);
    fine_.x = resampled(*src.mesh, src.x, fine_);
    if (!fine_.x.allFinite())
      throw UserError(src.path + ": the stored shape does not resample to a finite one");
    say("initial shape from " + src.path + " (Ca = " + std::to_string(src.ca) + ")");
  }

  // Adaptive time steps on grid g at Ca = ca from g.x until the node speed is below `speed`.
  // Returns the median of the last accepted steps (0 when none), or -1 when the march failed.
  double approach(Grid& g, double ca, double speed) {
    control::TimeOptions time = opt_.time;
    time.adaptive = true;
    g.cap->set_state(g.x, t_, steps_);
    TimeStepper st(*g.cap, time, g.h_last);
    capsule::HealthMonitor health(*g.mesh, g.x);
    const capsule::CaFunction level = [ca](double) { return ca; };
    const double t0 = t_;
    std::vector<double> steps;
    double v = std::numeric_limits<double>::infinity();
    while (v > speed || steps.size() < kMinApproachSteps) {
      apply_edits();
      if (stopped() || t_ - t0 > kMaxApproachTime) break;
      const Eigen::Matrix3Xd before = g.cap->positions();
      const TimeStepper::Outcome o = st.advance(t_ + 1.0, level, health);
      if (!o.failure.empty()) {
        failure_ = o.failure;
        return -1;  // g.x: the state the approach started from
      }
      t_ = g.cap->time();
      ++steps_;
      v = (g.cap->positions() - before).cwiseAbs().maxCoeff() / o.dt;
      steps.push_back(o.dt);
      if (progress_due()) {
        std::ostringstream m;
        m << "Ca=" << ca << " approach: t=" << fixed(t_ - t0, 3) << " node speed "
          << std::scientific << std::setprecision(2) << v << " (until " << speed << "), dt "
          << o.dt;
        log_->status(m.str());
      }
    }
    g.x = g.cap->positions();
    if (steps.empty()) return g.h_last;
    const size_t n = std::min<size_t>(steps.size(), 10);
    std::vector<double> last(steps.end() - n, steps.end());
    std::sort(last.begin(), last.end());
    g.h_last = last[n / 2];
    return g.h_last;
  }

  // Approach and Newton on grid g, up to kSolveAttempts times. False when stopped or when the
  // approach failed (failure_ says why); otherwise *sol is the last solve (failure_ says why
  // when it did not converge).
  bool solve_on(Grid& g, double ca, capsule::SteadySolution* sol, int* newton, long* krylov) {
    double speed = kApproachSpeed;
    for (int attempt = 0; attempt < kSolveAttempts; ++attempt, speed /= 4) {
      const double h = approach(g, ca, speed);
      if (&g == &fine_ && h > 0) h_ca_ = ca;
      if (h < 0) {
        failure_ = "the approach failed: " + failure_;
        approach_failed_ = true;
        return false;
      }
      if (stopped()) return false;
      capsule::SteadySolveOptions so;
      so.step = kMapStepFactor * h;
      so.tolerance = opt_.steady.solve_tolerance;
      so.stop = control_->stop();
      *sol = capsule::solve_steady(*g.cap, g.x, ca, so);
      *newton += sol->newton;
      *krylov += sol->krylov;
      std::ostringstream m;
      m << "Ca = " << ca << " (NB=" << g.mesh->nb() << "): Newton "
        << (sol->converged ? "converged" : "did not converge") << " (" << sol->message << ") in "
        << sol->newton << " iterations, " << sol->krylov << " GMRES iterations, residual "
        << std::scientific << std::setprecision(2) << sol->residual << " (map step " << so.step
        << ", approach to t = " << std::defaultfloat << t_ << ")";
      say(m.str());
      if (sol->converged) {
        g.x = sol->x;
        return true;
      }
      if (stopped()) return false;
    }
    failure_ = "no steady state found: " + sol->message + ", residual " + scientific(sol->residual);
    return true;
  }

  Grid coarse_grid() const {
    control::ControlOptions co = opt_;
    co.mesh.nb = kCoarseNb;
    return make_grid(co);
  }

  // The largest angle between the unit normals of neighbouring nodes of grid g's state: above
  // the health check's resolution limit the grid does not resolve the tips.
  static double normal_turning(const Grid& g) {
    return geometry::max_normal_turning(*g.mesh, geometry::compute_geometry(*g.mesh, g.x).n);
  }

  // The health check's node-to-node oscillation indicator of grid g's state.
  static double oscillation(const Grid& g) {
    return capsule::HealthMonitor(*g.mesh, g.x).oscillation_indicator(g.x);
  }

  static bool resolves_tips(double turning) {
    return turning <= capsule::HealthOptions{}.resolution_warn_angle;
  }

  // The first level from rest on a fine grid: solved on NB=8 first (cheap evaluations for the
  // long approach from the sphere) and resampled onto the fine grid as its starting state.
  // Returns whether that NB=8 state resolves its tips (false when there is none).
  bool coarse_start(double ca, int* newton, long* krylov, long* evaluations) {
    Grid coarse = coarse_grid();
    capsule::SteadySolution sol;
    const bool ran = solve_on(coarse, ca, &sol, newton, krylov);
    *evaluations += coarse.cap->velocity_evaluations();
    if (!ran || !sol.converged) {
      if (!stopped())
        say("the NB=" + std::to_string(kCoarseNb) + " start found no steady state (" + failure_ +
            "): from rest on NB=" + std::to_string(opt_.mesh.nb));
      failure_.clear();
      return false;
    }
    fine_.x = resampled(*coarse.mesh, coarse.x, fine_);
    say("Ca = " + fixed(ca, 6) + ": the NB=" + std::to_string(kCoarseNb) +
        " steady state resampled onto NB=" + std::to_string(opt_.mesh.nb));
    return resolves_tips(normal_turning(coarse));
  }

  // The smallest principal tension of the fine grid's state.
  double tau_min() const { return fine_.cap->fields(fine_.x).tension2.minCoeff(); }

  // The first level again, along the branch from a start that resolves its tips: Ca lowered
  // until the NB=8 state resolves them, that state solved on the fine grid, then the branch
  // followed up to ca (pseudo-arclength, landing on ca; Newton at fixed Ca fails near the top
  // of a steep branch). For a root with compressive tension found from an under-resolved NB=8
  // start: another root of the fine equations near the NB=8 state, not the shape a time march
  // settles in (the neo-Hookean Ca = 0.4 state at NE=14 NB=14). False when stopped, when no
  // start resolves its tips or when the branch does not reach ca (failure_ says why); fine_.x
  // and *sol are then unchanged.
  bool climb(double ca, capsule::SteadySolution* sol, int* newton, long* krylov,
             long* evaluations) {
    const Eigen::Matrix3Xd kept = fine_.x;
    const double kept_h = fine_.h_last, kept_h_ca = h_ca_;
    const auto give_up = [&](const std::string& why) {
      failure_ = why;
      fine_.x = kept;
      fine_.h_last = kept_h;
      h_ca_ = kept_h_ca;
      return false;
    };
    Grid coarse = coarse_grid();
    double low = ca;
    bool found = false;
    for (int k = 0; k < kClimbTries && !found && !stopped(); ++k) {
      low *= kClimbFactor;
      capsule::SteadySolution s;
      if (!solve_on(coarse, low, &s, newton, krylov) || !s.converged) {
        if (!stopped())
          say("climb: no NB=" + std::to_string(kCoarseNb) + " state at Ca = " + fixed(low, 6) +
              " (" + failure_ + ")");
        continue;  // the march's or Newton's failure there: lower Ca again
      }
      const double turning = normal_turning(coarse);
      found = resolves_tips(turning);
      say("climb: the NB=" + std::to_string(kCoarseNb) + " state at Ca = " + fixed(low, 6) +
          (found ? " resolves its tips" : " does not resolve its tips") + " (the normal turns by " +
          fixed(turning, 2) + " rad between neighbouring nodes)");
    }
    *evaluations += coarse.cap->velocity_evaluations();
    if (stopped()) return give_up("stopped");
    if (!found)
      return give_up("no NB=" + std::to_string(kCoarseNb) + " state down to Ca = " + fixed(low, 6) +
                     " resolves its tips");
    log_->event(Record().set("event", "climb").set("ca", ca).set("from_ca", low), t_);
    fine_.x = resampled(*coarse.mesh, coarse.x, fine_);
    capsule::SteadySolution s;
    if (!solve_on(fine_, low, &s, newton, krylov) || !s.converged)
      return give_up("Ca = " + fixed(low, 6) + ": " + failure_);
    capsule::ContinuationOptions co;
    co.from = low;
    co.to = ca;
    co.step = (ca - low) / kClimbStates;
    co.after_fold = 0;
    capsule::ArclengthContinuation branch(co, capsule::BranchPoint{flat(fine_.x), low});
    Corrections k;
    for (;;) {
      const capsule::ArclengthContinuation::Status status =
          branch.advance([&](const capsule::BranchPoint& p, const capsule::BranchPoint& n,
                             int* it) { return correct(p, n, &k, it); });
      *newton += k.newton;
      *krylov += k.krylov;
      k.newton = 0;
      k.krylov = 0;
      if (stopped()) return give_up("stopped");
      if (status == capsule::ArclengthContinuation::Status::Stuck)
        return give_up("the branch from Ca = " + fixed(low, 6) + " ends: " + branch.why());
      if (status == capsule::ArclengthContinuation::Status::Done) break;
      fine_.x = positions(branch.last());
    }
    if (std::abs(branch.last().ca - ca) > 1e-9 * ca)
      return give_up("the branch from Ca = " + fixed(low, 6) + " turns back at Ca = " +
                     fixed(branch.fold() ? branch.fold()->ca : branch.last().ca, 6) +
                     " before reaching " + fixed(ca, 6));
    if (const double a = oscillation(fine_); a > capsule::HealthOptions{}.oscillation_fail)
      return give_up("the branch reaches Ca = " + fixed(ca, 6) +
                     " with node-to-node oscillation (highest-mode amplitude " + scientific(a) +
                     " of the element size, above the time steps' limit " +
                     scientific(capsule::HealthOptions{}.oscillation_fail) +
                     "): NB=" + std::to_string(opt_.mesh.nb) +
                     " does not resolve the state there (raise mesh.nb)");
    *sol = k.last;
    return true;
  }

  bool solve_level(double ca) {
    solving_level_ = true;
    const bool ok = solve_level_now(ca);
    solving_level_ = false;
    return ok;
  }

  bool solve_level_now(double ca) {
    const auto t_level = std::chrono::steady_clock::now();
    const long evals0 = fine_.cap->velocity_evaluations();
    long evaluations = 0;
    int newton = 0;
    long krylov = 0;
    approach_failed_ = false;  // this level's
    bool resolved_start = true;
    if (states_ == 0 && opt_.start.from.empty() && opt_.mesh.nb > kCoarseNb)
      resolved_start = coarse_start(ca, &newton, &krylov, &evaluations);
    if (stopped()) return false;
    capsule::SteadySolution sol;
    bool ran = solve_on(fine_, ca, &sol, &newton, &krylov);
    if (stopped()) return false;
    if (!resolved_start) {
      // Where the NB=8 start does not resolve the tips (or found no state): no root, or a root
      // with compressive tension, is solved again along the branch from a lower Ca (climb).
      const bool found = ran && sol.converged;
      std::ostringstream m;
      if (!found)
        m << "Ca = " << ca << ": no steady state on NB=" << opt_.mesh.nb << " (" << failure_ << ")";
      else if (const double tau = tau_min(); tau < 0)
        m << "Ca = " << ca << ": the root on NB=" << opt_.mesh.nb
          << " has compressive tension (tau_min = " << tau << ")";
      if (!m.str().empty()) {
        say(m.str() + ", and the NB=" + std::to_string(kCoarseNb) +
            " start does not resolve the tips: solved again along the branch from a lower Ca");
        const std::string first_failure = failure_;
        const bool first_approach_failed = approach_failed_;
        if (climb(ca, &sol, &newton, &krylov, &evaluations)) {
          ran = true;
          approach_failed_ = false;
          failure_.clear();
        } else {
          if (stopped()) return false;
          say("climb: " + failure_ + (found ? "; the first root stands" : ""));
          failure_ = found ? first_failure : first_failure + "; climb: " + failure_;
          approach_failed_ = first_approach_failed;
        }
      }
    }
    evaluations += fine_.cap->velocity_evaluations() - evals0;
    evaluations_ += evaluations;
    if (!ran || !sol.converged) return fail(ca, failure_);
    write_state(ca, sol, newton, krylov, evaluations,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t_level).count());
    return true;
  }

  // The branch of a continuation from the first state (capsule/continuation.h), each state
  // solved on the hyperplane of its prediction (capsule::solve_steady_on_hyperplane).
  void follow_branch(SteadySummary* sum) {
    const control::Continuation& c = *opt_.ca.continuation;
    capsule::ContinuationOptions co;
    co.from = c.from;
    co.to = c.to;
    co.step = c.step;
    co.after_fold = c.after_fold;
    co.at = c.at;
    branch_ = std::make_unique<capsule::ArclengthContinuation>(
        co, capsule::BranchPoint{flat(fine_.x), c.from});
    capsule::ArclengthContinuation& branch = *branch_;
    for (;;) {
      between_states();
      if (stopped()) {
        say("stopped: the branch ends at Ca = " + fixed(branch.last().ca, 6));
        return;
      }
      const auto t_state = std::chrono::steady_clock::now();
      const long evals0 = fine_.cap->velocity_evaluations();
      Corrections k;
      const capsule::ArclengthContinuation::Status status =
          branch.advance([&](const capsule::BranchPoint& p, const capsule::BranchPoint& n,
                             int* newton) { return correct(p, n, &k, newton); });
      const long evaluations = fine_.cap->velocity_evaluations() - evals0;
      evaluations_ += evaluations;
      if (stopped()) continue;
      if (status == capsule::ArclengthContinuation::Status::Done) return;
      if (status == capsule::ArclengthContinuation::Status::Stuck) {
        sum->resolution_limit = true;
        sum->failure = branch.why();
        say("the branch ends: " + branch.why());
        log_->event(Record().set("event", "branch_end").set("message", branch.why()), t_);
        return;
      }
      fine_.x = positions(branch.last());
      if (branch.fold_found_now()) report_fold(*branch.fold(), c.after_fold, sum);
      write_state(
          branch.last().ca, k.last, k.newton, k.krylov, evaluations,
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t_state).count());
      ++sum->states;
    }
  }

  struct Corrections {
    capsule::SteadySolution last;
    int newton = 0;
    long krylov = 0;
  };

  // The continuation's corrector: the midpoint map step from adaptive steps measured near this Ca
  // (again when Ca moved by more than 20 % since), then Newton on the hyperplane.
  std::optional<capsule::BranchPoint> correct(const capsule::BranchPoint& p,
                                              const capsule::BranchPoint& normal, Corrections* k,
                                              int* newton) {
    if (std::abs(p.ca - h_ca_) > 0.2 * h_ca_) measure_step(p.ca);
    capsule::SteadySolveOptions so;
    so.step = kMapStepFactor * fine_.h_last;
    so.tolerance = opt_.steady.solve_tolerance;
    so.stop = control_->stop();
    k->last = capsule::solve_steady_on_hyperplane(*fine_.cap, p, normal, so);
    k->newton += k->last.newton;
    k->krylov += k->last.krylov;
    *newton = k->last.newton;
    std::ostringstream m;
    m << "branch: predicted Ca = " << p.ca << ", Newton "
      << (k->last.converged ? "converged" : "did not converge") << " at Ca = " << k->last.ca << " ("
      << k->last.message << ") in " << k->last.newton << " iterations, " << k->last.krylov
      << " GMRES iterations, residual " << std::scientific << std::setprecision(2)
      << k->last.residual;
    say(m.str());
    if (!k->last.converged) return std::nullopt;
    return capsule::BranchPoint{flat(k->last.x), k->last.ca};
  }

  // The stability limit at Ca: kMinApproachSteps adaptive steps from the last state (which
  // is kept, as is the simulated time).
  void measure_step(double ca) {
    const Eigen::Matrix3Xd x = fine_.x;
    const double t = t_, h = fine_.h_last;
    if (approach(fine_, ca, std::numeric_limits<double>::infinity()) < 0)
      fine_.h_last = h;  // the march failed: keep the last measurement
    else
      h_ca_ = ca;
    fine_.x = x;
    t_ = t;
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
    log_->event(Record()
                    .set("event", "fold")
                    .set("ca", f.ca)
                    .set("arclength", f.arclength)
                    .set("folds", folds_),
                t_);
  }

  static Eigen::VectorXd flat(const Eigen::Matrix3Xd& x) {
    return Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  }

  static Eigen::Matrix3Xd positions(const capsule::BranchPoint& p) {
    return Eigen::Map<const Eigen::Matrix3Xd>(p.y.data(), 3, p.y.size() / 3);
  }

  bool fail(double ca, const std::string& why) {
    failure_ = "Ca = " + std::to_string(ca) + ": " + why;
    say("failure: " + failure_);
    log_->event(Record().set("event", "failure").set("ca", ca).set("message", failure_), t_);
    return false;
  }

  // A warning about a steady state: said, and written to events.jsonl with its cause and the
  // quantity that raised it.
  void warn(const std::string& cause, double ca, const char* key, double value,
            const std::string& message) {
    say(message);
    log_->event(Record()
                    .set("event", "warning")
                    .set("cause", cause)
                    .set("ca", ca)
                    .set(key, value)
                    .set("message", message),
                t_);
  }

  // A root with compressive tension somewhere: the membrane (no bending stiffness) wrinkles
  // there at the scale of the mesh, so the shape is not resolved (below Ca ~ 0.15 in planar
  // extension).
  void warn_if_compressed(double ca, double tau_min) {
    if (tau_min >= 0) return;
    std::ostringstream m;
    m << "warning: compressive tension at the steady state at Ca = " << ca
      << " (tau_min = " << tau_min
      << "): the membrane wrinkles there (no bending stiffness), so this root is not a resolved "
         "steady shape";
    warn("compression", ca, "tau_min", tau_min, m.str());
  }

  // A root with node-to-node oscillation above the time steps' failure limit: a march from it
  // stops at its first step, and the grid does not resolve the shape.
  void warn_if_oscillating(double ca, double amplitude) {
    if (amplitude <= capsule::HealthOptions{}.oscillation_fail) return;
    std::ostringstream m;
    m << "warning: node-to-node oscillation at the steady state at Ca = " << ca
      << " (highest-mode amplitude " << amplitude << " of the element size, above the time steps' "
      << "limit " << capsule::HealthOptions{}.oscillation_fail << "): NB=" << opt_.mesh.nb
      << " does not resolve this root (raise mesh.nb)";
    warn("oscillation", ca, "amplitude", amplitude, m.str());
  }

  void write_state(double ca, const capsule::SteadySolution& sol, int newton, long krylov,
                   long evaluations, double wall_s) {
    diagnostics::ShapeOptions so;
    const diagnostics::ShapeDiagnostics d = diagnostics::measure_shape(*fine_.mesh, fine_.x, so);
    const membrane::MembraneFields f = fine_.cap->fields(fine_.x);
    const double drift = d.volume / fine_.cap->initial_volume() - 1.0;
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,"
                  "%.3e,%.3e,%.3e,%d,%ld,%ld,%.3f,%d\n",
                  t_, ca, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.area, d.edge_curvature,
                  f.tension1.maxCoeff(), f.tension2.minCoeff(), sol.residual, sol.speed, drift,
                  newton, krylov, evaluations, wall_s, folds_);
    dir_->steady().append(buf);
    std::ostringstream m;
    m << "steady state at Ca = " << ca << ": D = " << fixed(d.D, 6) << " L = " << fixed(d.L, 6)
      << " S = " << fixed(d.S, 6) << " W = " << fixed(d.W, 6) << " (" << evaluations
      << " velocity evaluations, " << fixed(wall_s, 1) << " s)";
    say(m.str());
    warn_if_compressed(ca, f.tension2.minCoeff());
    warn_if_oscillating(ca, oscillation(fine_));
    const std::string ckpt = write_checkpoint(ca);
    submit_frame(ca, d, f);
    log_->event(Record()
                    .set("event", "steady")
                    .set("ca", ca)
                    .set("D", d.D)
                    .set("L", d.L)
                    .set("residual", sol.residual)
                    .set("newton", newton)
                    .set("krylov", krylov)
                    .set("velocity_evaluations", evaluations)
                    .set("checkpoint", ckpt),
                t_);
  }

  // A level failed (exit 4): its last good state is kept. That is the last steady state when
  // there is one (its checkpoint is written); else the fine grid's capsule as the failed march
  // left it (the time steps keep the last state that passed the health check).
  void keep_last_good_state(double ca) {
    if (states_ > 0) {
      say("last good state: the steady state of " +
          RunDirectory::checkpoints(dir_->path()).front().string());
      return;
    }
    try {
      const std::string ckpt = write_checkpoint(
          ca, fine_.cap->positions(), fine_.cap->time(),
          "the last good state of capflow steady's march to Ca = " + fixed(ca, 6) +
              " before it failed (not a steady state)");
      say("last good state (t = " + fixed(fine_.cap->time(), 4) + ", not steady) kept in " + ckpt);
    } catch (const OutputError& e) {
      say(std::string("the last good state could not be kept: ") + e.what());
    }
  }

  // The state as a checkpoint of a run held at this Ca (start.from, render, figure, --resume).
  std::string write_checkpoint(double ca) {
    return write_checkpoint(ca, fine_.x, t_, "steady state by capflow steady");
  }

  std::string write_checkpoint(double ca, const Eigen::Matrix3Xd& x, double t,
                               const std::string& note) {
    RunCheckpoint c;
    c.options = opt_;
    c.options.ca = control::CaSchedule{};
    control::CaSegment hold;
    hold.ca = ca;
    c.options.ca.segments.push_back(hold);
    c.options.time.t_end = std::max(opt_.time.t_end, t + 1.0);
    c.control = control::to_json_text(c.options);
    c.control_file = c.control;
    c.x = x;
    c.t = t;
    c.steps = steps_;
    c.ca = ca;
    c.schedule = control::CaScheduler(c.options.ca, c.options.steady, t, ca).state();
    const capsule::HealthMonitor h(*fine_.mesh, x);
    c.health_normals = h.normals();
    c.health_flags = h.flags();
    c.wall_s = wall();
    c.note = note;
    dir_->subdirectory("checkpoints");
    const fs::path path = dir_->checkpoint_path(++states_);
    write_run_checkpoint(c, path.string());
    return path.string();
  }

  // x on `from`'s mesh carried onto grid g's (geometry::resample_surface), at the reference
  // volume.
  static Eigen::Matrix3Xd resampled(const geometry::Mesh& from, const Eigen::Matrix3Xd& x,
                                    const Grid& g) {
    const Eigen::Matrix3Xd y = geometry::resample_surface(from, x, *g.mesh);
    return y.allFinite() ? capsule::rescale_to_volume(*g.mesh, y, g.cap->initial_volume()) : y;
  }

  control::ControlOptions opt_;
  control::ControlOptions file_opt_;  // the control file as last read (live edits)
  control::CaSchedule previous_ca_;   // "ca" before the edit being applied
  std::string control_path_;
  std::unique_ptr<SteadyControl> control_;
  std::unique_ptr<capsule::ArclengthContinuation> branch_;
  std::unique_ptr<render::RenderThread> renderer_;
  long frames_ = 0;
  int folds_ = 0;               // folds the continuation passed
  bool solving_level_ = false;  // a level's approach and solve are under way (levels_[states_])
  std::vector<double> levels_;
  std::unique_ptr<RunDirectory> dir_;
  std::unique_ptr<RunLog> log_;
  Grid fine_;        // the control file's mesh
  double t_ = 0;     // simulated time of all approaches
  double h_ca_ = 0;  // the Ca at which fine_.h_last was measured
  long steps_ = 0;   // their steps
  long states_ = 0;
  double last_progress_ = 0;
  long evaluations_ = 0;
  bool approach_failed_ = false;  // the last failure was the time steps' (health check)  //
                                  // velocity evaluations of the levels done, on every grid
  std::string failure_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace

SteadySummary run_steady(const control::ControlOptions& options, bool overwrite,
                         const std::atomic<bool>* stop,
                         const std::optional<SteadyControlFile>& live) {
  SteadyRun r(options, overwrite, live);
  return r.run(stop);
}

}  // namespace capflow::app
