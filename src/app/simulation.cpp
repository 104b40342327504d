// capflow/app/simulation: see simulation.h.
#include "app/simulation.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <thread>

#include "app/console.h"
#include "app/cpu_budget.h"
#include "app/errors.h"
#include "app/format.h"
#include "app/frames.h"
#include "app/output_cadence.h"
#include "app/progress.h"
#include "app/run_checkpoint.h"
#include "app/run_lines.h"
#include "app/run_outputs.h"
#include "app/time_stepper.h"
#include "app/worker_team.h"
#include "capsule/capsule.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "control/schedule.h"
#include "output/records.h"
#include "parallel/team.h"

namespace capflow::app {

using control::Record;

namespace {

// What observe() found after a step.
struct Observation {
  Measures m;
  bool measured = false;
  // Ca in force during the step that ended here: the rows, frames and surfaces of this time
  // carry it (at a level change the new Ca applies from this time on, to the next step).
  double ca = 0;
  control::CaScheduler::Event schedule;
};


RunLifecycle::Spec run_spec(std::function<void(const std::optional<RunCheckpoint>&)> check) {
  RunLifecycle::Spec spec;
  spec.command = control::Command::Run;
  spec.timeseries_header = output::records::timeseries().header();
  spec.steady_header = output::records::steady_run().header();
  spec.check = std::move(check);
  return spec;
}

}  // namespace

struct Simulation::Impl {
  std::unique_ptr<RunLifecycle> life;
  control::ControlOptions opt;       // effective
  control::ControlOptions file_opt;  // the control file as last read: the base of live edits
  std::unique_ptr<geometry::Mesh> mesh;
  std::unique_ptr<capsule::Capsule> cap;
  std::unique_ptr<capsule::HealthMonitor> health;
  std::unique_ptr<TimeStepper> stepper;
  std::unique_ptr<control::CaScheduler> schedule;
  std::unique_ptr<OutputCadence> cadence;
  std::unique_ptr<RunOutputs> out;
  double last_dt = 0;          // the step that ended at t() (0 before the first)
  long rejected = 0;           // adaptive step attempts refused in this session
  bool at_breakpoint = false;  // the last step ended where the Ca schedule changes
  long resumes = 0;
  bool checkpoint_now_seen = false;
  double next_sample = 0;      // next shape sample for the steady-state test
  std::string thread_warning;  // numerics.threads cut at the start (logged with the start)

  double t() const { return cap->time(); }
  void say(const std::string& line) { life->say(line); }
  void event(Record e) { life->event(std::move(e), cap ? cap->time() : 0.0); }

  // ---- set-up -------------------------------------------------------------------------------

  // The mesh and the capsule at rest (a resume or start.from sets its state afterwards).
  void build_solver() {
    std::string warning;
    set_solver_threads(opt.numerics.threads, &warning);
    if (!warning.empty()) thread_warning = warning;
    mesh = control::make_mesh(opt.mesh);
    cap = std::make_unique<capsule::Capsule>(*mesh, opt.law, opt.flow,
                                             control::dynamics_options(opt));
    attach_team(*cap, opt);  // the ranks of an MPI run share its velocity evaluations
    out = std::make_unique<RunOutputs>(*life, opt);
  }

  // h_next, history: the adaptive integrator's first step and controller state (from a
  // checkpoint; 0 and none = estimate anew).
  void start_monitors(std::optional<double> initial_ca, double h_next = 0,
                      const std::optional<TimeStepper::History>& history = std::nullopt) {
    health = std::make_unique<capsule::HealthMonitor>(*mesh, cap->positions());
    stepper = std::make_unique<TimeStepper>(*cap, opt.time, h_next, history);
    schedule = std::make_unique<control::CaScheduler>(opt.ca, opt.steady, cap->time(), initial_ca);
    cadence = std::make_unique<OutputCadence>(opt.output, cap->time());
    next_sample = cap->time();
  }

  StateRecord record(const Measures& m, double ca) {
    return {cap.get(), ca, m, last_dt, life->wall(), schedule.get(), RunPhase::Running,
            opt.time.t_end};
  }

  // ---- checkpoints --------------------------------------------------------------------------

  RunCheckpoint checkpoint_state() const {
    RunCheckpoint s;
    s.options = opt;
    s.control = control::to_json_text(opt);
    s.control_file = control::to_json_text(file_opt);
    s.x = cap->positions();
    s.t = cap->time();
    s.steps = cap->step_count();
    s.ca = schedule->ca(cap->time());
    s.schedule = schedule->state();
    s.health_normals = health->normals();
    s.health_flags = health->flags();
    out->store(&s);
    s.resumes = resumes;
    s.wall_s = life->wall();
    s.checkpoint_now_seen = checkpoint_now_seen;
    s.h_next = stepper->adaptive() ? stepper->next_step() : 0.0;
    if (stepper->adaptive()) s.step_history = stepper->history();
    s.krylov_warm = cap->krylov_warm_start();
    return s;
  }

  void write_checkpoint(const std::string& why) {
    const std::filesystem::path path =
        life->store_checkpoint([&] { return checkpoint_state(); }, cap->step_count());
    RunDirectory& dir = life->dir();
    dir.prune_checkpoints(3);
    event(Record()
              .set("event", "checkpoint")
              .set("file", path.string())
              .set("why", why)
              .set("steps", cap->step_count()));
    dir.log().append("[" + iso_now() + "] checkpoint " + path.string() + " (" + why + ")\n");
  }

  // ---- the four parts of a loop iteration ---------------------------------------------------

  // capflow run's edit policy: every live key; a continuation is capflow steady's.
  static control::EditPolicy policy() {
    control::EditPolicy p;
    p.command = control::Command::Run;
    p.veto = [](const control::OptionChange& c, const control::ControlOptions& merged) {
      return c.path == "ca" && merged.ca.continuation ? std::string(control::kContinuationRefused)
                                                      : std::string();
    };
    return p;
  }

  // The saved edits of the control file (step boundary) and run.checkpoint_now.
  void apply_edits() {
    for (;;) {
      const double now = t();
      const double ca_before = schedule->ca(now);
      const control::OutputOptions before = opt.output;
      std::optional<RunLifecycle::Edit> e = life->next_edit(&opt, &file_opt, policy(), now);
      if (!e) break;
      const control::EditResult& r = e->result;
      cap->set_volume_correction(opt.numerics.volume_correction);
      stepper->configure(opt.time);
      if (r.steady_changed) schedule->set_steady(opt.steady);
      std::string note;
      if (r.schedule_changed) {
        const std::string what = schedule->edit(opt.ca, now);
        stepper->restart();  // Ca may jump here
        std::ostringstream m;
        m << "Ca " << ca_before << " -> " << schedule->ca(now) << " (" << what << ")";
        note = m.str();
      }
      std::string thread_cut;
      set_solver_threads(opt.numerics.threads, &thread_cut);
      cadence->edit(before, opt.output, now);
      out->set_options(opt);
      life->report_edit(*e, now, note, Record().set("ca", schedule->ca(now)));
      if (!thread_cut.empty()) life->warn("threads", thread_cut, now);
    }
    if (opt.run.checkpoint_now && !checkpoint_now_seen) write_checkpoint("run.checkpoint_now");
    checkpoint_now_seen = opt.run.checkpoint_now;
  }

  // One step and the health check (on failure the last good state is kept). Adaptive steps
  // end at t_end, the next output time or the next change of the Ca schedule at the latest.
  // Returns "" or why no step could be taken.
  std::string advance() {
    const double breakpoint = schedule->next_breakpoint(t());
    const double t_stop = std::min({opt.time.t_end, cadence->next_time(), breakpoint});
    const TimeStepper::Outcome o = stepper->advance(
        t_stop, [&](double tt) { return schedule->ca(tt); }, *health);
    // An adaptive step that ended on the schedule's change: the schedule sees it now.
    at_breakpoint = stepper->adaptive() && o.failure.empty() && t() == breakpoint;
    for (const capsule::HealthReport& w : o.warnings) life->warn(w.cause, w.message, t());
    if (o.failure.empty()) last_dt = o.dt;
    rejected += o.rejected;
    return o.failure;
  }

  // Diagnostics as the outputs due need them, and the Ca schedule's shape sample.
  Observation observe(const Due& due, double dt) {
    Observation ob;
    const double now = t();
    ob.ca = schedule->ca(now);
    const double eps = 1e-9 * dt;
    const bool sample = now >= next_sample - eps || at_breakpoint;
    if (!sample && !due.full_measure()) return ob;
    ob.m = measure_state(*cap, due.full_measure());
    ob.measured = true;
    if (sample) {
      // Shape samples for steady-state detection: about 20 per window.
      next_sample = now + std::min(opt.steady.window / 20.0, opt.output.csv_every) - eps;
      ob.schedule = schedule->sample(now, ob.m.shape.L, ob.m.shape.S, ob.m.shape.W);
      if (ob.schedule.steady && !due.full_measure()) ob.m = measure_state(*cap, true);
    }
    return ob;
  }

  // Reports this step's state to the outputs due. Returns true when the run should stop at a
  // steady state.
  bool emit(const Observation& ob, const Due& due) {
    const double now = t();
    const control::CaScheduler::Event& ev = ob.schedule;
    out->begin(due, ob.ca, ev.steady ? std::optional<double>(ev.steady_ca) : std::nullopt);
    const StateRecord s = record(ob.m, ob.ca);
    bool stop_here = false;
    if (ev.steady) {
      out->write_steady(s);
      if (opt.steady.stop && schedule->in_final_hold()) stop_here = true;
    }
    if (ev.steady || ev.level_changed) {
      say(ev.description);
      event(Record()
                .set("event", ev.steady ? "steady" : "level")
                .set("message", ev.description)
                .set("ca", ev.steady ? ev.steady_ca : schedule->ca(now))
                .set("D", ob.m.shape.D)
                .set("L", ob.m.shape.L));
    }
    out->write_due(s);
    if (due.full_measure()) {
      out->offer_preview(s);
      if (!opt.bending.enabled()) warn_if_wrinkling(ob, now);
    }
    if (due.checkpoint) write_checkpoint("output.checkpoint_every");
    cadence->fired(due, opt.output, now);
    return stop_here;
  }

  // Compressive tension in a membrane without bending stiffness (with bending it is resolved).
  void warn_if_wrinkling(const Observation& ob, double now) {
    const capsule::HealthReport w =
        health->check_wrinkling(now, ob.m.tau_min, ob.m.tau_min_at, schedule->max_rate());
    if (w.level == capsule::HealthLevel::Warning) life->warn(w.cause, w.message, now);
  }

  void report_progress(Progress& progress, const Observation& ob, double D) {
    if (!progress.due()) return;
    const double now = t();
    const double rate = progress.rate(cap->step_count());
    const double eta = (opt.time.t_end - now) / std::max(progress.time_rate(now), 1e-12);
    RunProgress p;
    p.t = now;
    p.ca = schedule->ca(now);
    p.D = ob.measured ? ob.m.shape.D : D;
    p.dt = last_dt;
    p.steps_per_s = rate;
    p.eta_s = eta;
    p.eta_steady = schedule->eta_steady(now);
    life->log().status(progress_line(p));
  }

  // ---- the session --------------------------------------------------------------------------

  void announce(bool fresh) {
    std::string line = run_banner(opt, *cap, life->dir().path().string());
    if (life->feed().watching())
      line += "; watching " + life->control_source() +
              (life->feed().using_inotify() ? " (inotify)" : " (polling)");
    say(line);
    say("Ca schedule: " + schedule->describe(t()));
    if (fresh)
      event(Record().set("event", "start").set_json("control", control::to_json_text(opt)));
    if (!thread_warning.empty()) life->warn("threads", thread_warning, t());
  }

  // The end of the loop: a checkpoint, the renderer's end. Output failures throw.
  void finish(RunTermination why) {
    write_checkpoint(reason_of(why));
    if (life->renderer()) say(render_report(life->stop_renderer()));
  }

  // An output failure: the state kept if the disk still takes a checkpoint - none when frames
  // were lost in the renderer's queue: the last one stays, and a resume makes them again.
  // False when the run never wrote a checkpoint: its start failed, and it is undone.
  bool keep_after_output_failure(const OutputError& e) {
    return life->keep_after_output_failure(e, t(), [&] {
      if (const long lost = out->frames_lost_in_flight(); lost > 0) {
        life->best_effort([&] {
          say(std::to_string(lost) + " frame(s) in the renderer's queue were not written: no " +
              "checkpoint of this state (a resume makes them again from the last one)");
        });
        return;
      }
      write_checkpoint("output failure");
    });
  }

  void summarise(RunSummary* sum) {
    const Measures m = measure_state(*cap, true);
    sum->reason = reason_of(sum->termination);
    sum->t = t();
    sum->steps = cap->step_count();
    sum->rejected = rejected;
    sum->evaluations = cap->velocity_evaluations();
    sum->krylov_iterations = cap->krylov_iterations();
    sum->viscosity_ratio = opt.viscosity_ratio != 1.0;
    sum->wall_s = life->wall();
    sum->D = m.shape.D;
    sum->L = m.shape.L;
    sum->S = m.shape.S;
    sum->W = m.shape.W;
    sum->volume_drift = m.shape.volume / cap->initial_volume() - 1.0;
    sum->steady_rows = out->steady_rows();
  }
};

Simulation::Simulation() : impl_(std::make_unique<Impl>()) {}

Simulation::Simulation(const control::ControlOptions& options, const std::string& control_source)
    : Simulation(NewRun{options, options, control_source, false}) {}

Simulation::Simulation(const NewRun& run) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.opt = run.options;
  s.file_opt = run.file_options;
  std::optional<double> initial_ca;
  s.life = RunLifecycle::create(
      run, run_spec([&](const std::optional<RunCheckpoint>& source) {
        if (source) initial_ca = source->ca;
        try {
          const control::CaScheduler probe(s.opt.ca, s.opt.steady, 0.0, initial_ca);
          (void)probe;
        } catch (const std::invalid_argument& e) {
          throw UserError(e.what());
        }
      }),
      nullptr);
  try {
    s.build_solver();
    if (s.life->source())
      s.cap->set_state(s.life->start_shape(*s.mesh, s.cap->initial_volume(), s.opt),
                       s.life->source()->t, 0);
    s.start_monitors(initial_ca);
    s.checkpoint_now_seen = run.options.run.checkpoint_now;
    s.life->start_renderer(s.opt, s.opt.output.frame_every > 0);
  } catch (...) {
    // A start that failed leaves nothing behind: the same command works once the cause is gone.
    s.life->abandon();
    throw;
  }
}

std::string Simulation::latest_checkpoint(const std::string& run_dir) {
  const std::vector<std::filesystem::path> all = RunDirectory::checkpoints(run_dir);
  return all.empty() ? "" : all.front().string();
}

std::unique_ptr<Simulation> Simulation::resume(const std::string& run_dir,
                                               const ResumeOverrides& ov) {
  std::unique_ptr<Simulation> sim(new Simulation());
  Impl& s = *sim->impl_;
  s.life = RunLifecycle::resume(run_dir, run_spec([&](const std::optional<RunCheckpoint>& c) {
                                  s.opt = c->options;
                                  if (ov.t_end) s.opt.time.t_end = *ov.t_end;
                                  const std::vector<control::ControlIssue> ti =
                                      control::time_issues(s.opt.time, c->t);
                                  if (!ti.empty())
                                    throw UserError(
                                        std::string(ov.t_end ? "--t-end" : "time.t_end") + ": " +
                                        ti[0].message + (ov.t_end ? "" : "; give --t-end to run on"));
                                }),
                                nullptr);
  const RunCheckpoint& c = *s.life->resumed_from();
  s.opt.output.dir = run_dir;
  s.opt.run.state = control::RunState::Running;
  s.file_opt = c.file_options;
  s.build_solver();
  s.cap->set_state(c.x, c.t, c.steps);
  try {
    s.cap->set_krylov_warm_start(c.krylov_warm);
  } catch (const std::invalid_argument& e) {
    throw UserError(c.path + ": " + e.what());
  }
  s.start_monitors(c.ca, c.h_next, c.step_history);
  try {
    s.schedule->restore(c.schedule);
    s.health->restore(c.health_normals, c.health_flags);
  } catch (const std::invalid_argument& e) {
    throw UserError(c.path + ": " + e.what());
  }
  s.out->restore(c);
  s.resumes = c.resumes + 1;
  s.checkpoint_now_seen = c.checkpoint_now_seen;
  s.life->write_control(s.opt);
  s.life->start_renderer(s.opt, s.opt.output.frame_every > 0);
  return sim;
}

Simulation::~Simulation() = default;

const control::ControlOptions& Simulation::options() const {
  return impl_->opt;
}

RunOutputs& Simulation::outputs() {
  return *impl_->out;
}

RunLifecycle& Simulation::lifecycle() {
  return *impl_->life;
}

RunSummary Simulation::run(const std::atomic<bool>* stop) {
  Impl& s = *impl_;
  Progress progress(s.life->log().tty());
  progress.start(s.cap->step_count(), s.t());
  RunSummary sum;
  const bool fresh = s.cap->step_count() == 0 && s.out->rows() == 0;
  RunTermination why = RunTermination::TEndReached;
  Observation last;
  bool was_paused = false;
  try {
    s.announce(fresh);
    last.m = measure_state(*s.cap, true);
    last.measured = true;
    if (fresh) {
      Due first;
      first.row = true;
      first.frame = s.opt.output.frame_every > 0;
      first.vtk = s.opt.output.vtk_every > 0;
      s.out->begin(first, s.schedule->ca(s.t()));
      // The checkpoint first: it records the outputs of t = 0 as due, and no frame is in flight.
      s.write_checkpoint("start");
      s.life->begun();
      s.out->write_due(s.record(last.m, s.schedule->ca(s.t())));
    } else if (s.out->pending()) {
      const StateRecord r = s.record(last.m, 0.0);
      s.out->write_steady(r);
      s.out->write_due(r);
      s.say("wrote the outputs of t = " + std::to_string(s.t()) +
            " that the output failure left out");
    }
    for (;;) {
      s.apply_edits();
      if (stop && stop->load()) {
        why = RunTermination::Signal;
        break;
      }
      if (s.opt.run.state == control::RunState::Stopped) {
        why = RunTermination::Stopped;
        break;
      }
      const bool paused = s.life->paused(s.opt, s.t());
      if (paused != was_paused) {
        if (paused)
          progress.pause();
        else
          progress.unpause();
        was_paused = paused;
        StateRecord r = s.record(last.m, s.schedule->ca(s.t()));
        r.phase = paused ? RunPhase::Paused : RunPhase::Running;
        s.out->notify(r);
      }
      if (paused) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      if (s.stepper->done(s.opt.time.t_end)) break;
      const std::string failure = s.advance();
      if (!failure.empty()) {
        sum.failed = true;
        sum.failure = failure;
        s.say("failure: " + failure + " (keeping the last good state, t = " +
              std::to_string(s.t()) + ")");
        s.event(Record().set("event", "failure").set("message", failure));
        why = RunTermination::SimulationFailed;
        break;
      }
      const double dt = s.last_dt;
      const Due due = s.cadence->due(s.t(), dt);
      const double D_before = last.m.shape.D;
      Observation ob = s.observe(due, dt);
      sum.steady_states += ob.schedule.steady;
      const bool stop_here = s.emit(ob, due);
      if (ob.schedule.level_changed) s.stepper->restart();  // Ca may jump here
      if (ob.measured) last = ob;
      s.report_progress(progress, ob, D_before);
      if (stop_here) {
        why = RunTermination::SteadyStop;
        break;
      }
    }
    s.finish(why);
  } catch (const OutputError& e) {
    sum.output_failed = true;
    sum.failure = e.what();
    why = RunTermination::OutputFailed;
    if (!s.keep_after_output_failure(e)) {
      sum.termination = why;
      sum.reason = reason_of(why);
      return sum;
    }
  }
  sum.termination = why;
  StateRecord end = s.record(last.m, s.schedule->ca(s.t()));
  end.phase = why == RunTermination::TEndReached || why == RunTermination::SteadyStop
                  ? RunPhase::Finished
                  : RunPhase::Stopped;
  s.out->notify(end);
  s.summarise(&sum);
  s.life->end(sum.BriefReport(), sum.end_event(), s.t());
  return sum;
}

}  // namespace capflow::app
