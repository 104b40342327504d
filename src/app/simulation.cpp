#include "app/simulation.h"

#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>
#include <tuple>

#include "app/console.h"
#include "app/cpu_budget.h"
#include "app/errors.h"
#include "app/frames.h"
#include "app/output_cadence.h"
#include "app/progress.h"
#include "app/run_checkpoint.h"
#include "app/run_directory.h"
#include "app/run_log.h"
#include "app/surface_export.h"
#include "app/surface_files.h"
#include "app/time_stepper.h"
#include "app/worker_team.h"
#include "capsule/capsule.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "control/edit.h"
#include "control/record.h"
#include "control/schedule.h"
#include "control/watcher.h"
#include "diagnostics/diagnostics.h"
#include "figures/run_tables.h"
#include "files/input_file.h"
#include "geometry/surface.h"
#include "membrane/membrane.h"
#include "output/vtk.h"
#include "parallel/team.h"
#include "render/render_thread.h"
#include "render/snapshot.h"
#include "spectral/simd_width.h"

namespace capflow::app {

namespace fs = std::filesystem;
using control::Record;

int RunSummary::exit_code() const {
  return outcome_exit_code(failed, output_failed);
}

namespace {

const char* const kTimeseriesHeader =
    "t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,inclination_deg,"
    "volume_drift,steps,dt,wall_s\n";
const char* const kSteadyHeader = "t,ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min\n";

struct Measures {
  diagnostics::ShapeDiagnostics shape;
  double tau_max = 0, tau_min = 0;
  Eigen::Vector3d tau_min_at = Eigen::Vector3d::Zero();
};

// What observe() found after a step.
struct Observation {
  Measures m;
  bool measured = false;
  // Ca in force during the step that ended here: the rows, frames and surfaces of this time
  // carry it (at a level change the new Ca applies from this time on, to the next step).
  double ca = 0;
  control::CaScheduler::Event schedule;
};

// "the step from t = ... failed" or "" after advance().
struct StepOutcome {
  std::string failure;
};

// 0.001, 1e-06: a number as a person would write it.
std::string fixed_or_sci(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

// An output writer's exception (vtk, pvd) as an output failure naming the file.
template <class F>
void as_output(const std::string& what, F&& f) {
  try {
    f();
  } catch (const OutputError&) {
    throw;
  } catch (const std::exception& e) {
    throw OutputError(what + ": " + e.what());
  }
}

// The movie of this session: the first of movie.mp4, movie.part2.mp4, ... that does not exist
// (a session whose movie could not hold a frame left none).
std::string movie_name(const RunDirectory& dir) {
  std::error_code ec;
  if (!fs::exists(dir.file("movie.mp4"), ec)) return "movie.mp4";
  for (int k = 2;; ++k) {
    const std::string name = "movie.part" + std::to_string(k) + ".mp4";
    if (!fs::exists(dir.file(name), ec)) return name;
  }
}

// A resume continues from its checkpoint: the frames and profiles written after it (index >=
// frames) are made again, so the ones on disk go (a session that ends earlier leaves none that
// belong to no state of the run).
void remove_outputs_after(const RunDirectory& dir, long frames) {
  std::error_code ec;
  for (const auto& [sub, prefix, ext] :
       {std::tuple<const char*, const char*, const char*>{"frames", "frame_", ".png"},
        {"profiles", "profile_", ".csv"}}) {
    for (const auto& e : fs::directory_iterator(dir.file(sub), ec)) {
      const std::string n = e.path().filename().string();
      if (n.rfind(prefix, 0) != 0 || e.path().extension() != ext) continue;
      char* end = nullptr;
      const long index = std::strtol(n.c_str() + std::strlen(prefix), &end, 10);
      if (end && std::string(end) == ext && index >= frames) fs::remove(e.path(), ec);
    }
  }
}

}  // namespace

struct Simulation::Impl {
  control::ControlOptions opt;       // effective
  control::ControlOptions file_opt;  // the control file as last read: the base of live edits
  std::unique_ptr<RunDirectory> dir;
  std::unique_ptr<RunLog> log;
  std::string control_source;
  std::unique_ptr<control::FileWatcher> watcher;
  bool check_file_now = false;  // resume: apply what was edited while the run was stopped
  std::unique_ptr<geometry::Mesh> mesh;
  std::unique_ptr<capsule::Capsule> cap;
  std::unique_ptr<capsule::HealthMonitor> health;
  std::unique_ptr<TimeStepper> stepper;
  double last_dt = 0;          // the step that ended at t() (0 before the first)
  long rejected = 0;           // adaptive step attempts refused in this session
  bool at_breakpoint = false;  // the last step ended where the Ca schedule changes
  std::unique_ptr<control::CaScheduler> schedule;
  std::unique_ptr<render::RenderThread> renderer;
  std::unique_ptr<output::PvdCollection> pvd;
  std::unique_ptr<OutputCadence> cadence;
  long frames = 0, rows = 0, steady_rows = 0, resumes = 0, vtk_index = 0;
  long session_first_frame = 0;  // the frame index this session started at
  bool checkpoint_now_seen = false;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  double wall_offset = 0;  // wall seconds of earlier sessions of this run
  double next_sample = 0;  // next shape sample for the steady-state test
  // Outputs due at the current step that are not written yet. After an output failure the
  // checkpoint records them and a resume writes them first, so that no row or frame is missing.
  Due pending;
  double pending_ca = 0;  // the Ca those outputs carry
  double pending_steady_ca = NAN;
  bool paused_logged = false;
  bool fresh_start = false;  // a new run (not a resume): its start may be abandoned
  std::string thread_warning;  // numerics.threads cut at the start (logged once the log exists)

  double wall() const {
    return wall_offset +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  double t() const { return cap->time(); }
  void say(const std::string& line) { log->say(line); }
  void event(Record e) { log->event(std::move(e), cap ? cap->time() : 0.0); }
  void warn(const std::string& cause, const std::string& message) {
    say("warning: " + message);
    event(Record().set("event", "warning").set("cause", cause).set("message", message));
  }

  // ---- set-up -------------------------------------------------------------------------------

  // A new run that failed before its first checkpoint: the renderer stopped and what it wrote
  // removed (RunDirectory::abandon).
  void abandon_start() {
    if (!fresh_start || !dir) return;
    if (renderer) {
      renderer->stop();
      renderer.reset();
    }
    log.reset();
    dir->abandon();
    fresh_start = false;
  }

  // The mesh and the capsule at rest (a resume or start.from sets its state afterwards).
  void build_solver() {
    std::string warning;
    set_solver_threads(opt.numerics.threads, &warning);
    if (!warning.empty()) thread_warning = warning;
    mesh = control::make_mesh(opt.mesh);
    cap = std::make_unique<capsule::Capsule>(*mesh, opt.law, opt.flow,
                                             control::dynamics_options(opt));
    attach_team(*cap, opt);  // the ranks of an MPI run share its velocity evaluations
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

  // "start.from": the source's shape resampled onto this run's mesh; time goes on from its t.
  void start_from(const RunCheckpoint& src) {
    Eigen::Matrix3Xd x = geometry::resample_surface(*src.mesh, src.x, *mesh);
    if (!x.allFinite())
      throw UserError(src.path + ": the stored shape does not resample to a finite one");
    const double drift_before = capsule::enclosed_volume(*mesh, x) / cap->initial_volume() - 1.0;
    if (opt.start.restore_volume) x = capsule::rescale_to_volume(*mesh, x, cap->initial_volume());
    cap->set_state(x, src.t, 0);
    std::ostringstream m;
    m << "initial shape from " << src.path << " (NE=" << src.mesh->ne() << " NB=" << src.mesh->nb()
      << ", t = " << src.t << ", Ca = " << src.ca << ") resampled onto NE=" << mesh->ne()
      << " NB=" << mesh->nb() << "; its volume drift " << drift_before
      << (opt.start.restore_volume ? " was removed (start.restore_volume)" : " is kept");
    say(m.str());
    event(Record()
              .set("event", "start_from")
              .set("checkpoint", src.path)
              .set("source_elements", src.mesh->ne())
              .set("source_nb", src.mesh->nb())
              .set("source_ca", src.ca)
              .set("volume_drift_before", drift_before)
              .set("restore_volume", opt.start.restore_volume));
  }

  void start_renderer() {
    renderer = app::start_renderer(opt, *dir, movie_name(*dir), opt.output.frame_every > 0,
                                   [this](const std::string& line) { say(line); });
  }

  void write_effective_control() { dir->write_text("control.json", control::to_json_text(opt)); }

  // ---- measuring and writing ----------------------------------------------------------------

  Measures measure(bool full) const {
    Measures m;
    diagnostics::ShapeOptions so;
    so.axes = opt.flow.type == capsule::FlowType::SimpleShear ? diagnostics::AxesMode::Shear
                                                              : diagnostics::AxesMode::FlowAxes;
    so.extrema = full;
    so.edge_curvature = full;
    m.shape = diagnostics::measure_shape(*mesh, cap->positions(), so);
    if (full) {
      const membrane::MembraneFields f = cap->fields(cap->positions());
      Eigen::Index imax, imin;
      m.tau_max = f.tension1.maxCoeff(&imax);
      m.tau_min = f.tension2.minCoeff(&imin);
      m.tau_min_at = cap->positions().col(imin);
    }
    return m;
  }

  render::Snapshot snapshot(const Measures& m, double ca) const {
    return state_snapshot(*cap, cap->positions(), cap->time(), ca,
                          membrane::to_string(opt.law.kind),
                          {m.shape.D, m.shape.L, m.shape.S, m.shape.W, m.tau_max, m.tau_min});
  }

  void write_row(const Measures& m, double ca) {
    const auto& d = m.shape;
    char buf[640];
    std::snprintf(buf, sizeof buf,
                  "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.12g,%.10g,%.10g,"
                  "%.10g,%.8g,%.6e,%ld,%.6g,%.3f\n",
                  cap->time(), ca, d.D, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.area, d.volume,
                  d.edge_curvature, m.tau_max, m.tau_min, d.inclination_deg,
                  d.volume / cap->initial_volume() - 1.0, cap->step_count(), last_dt, wall());
    dir->timeseries().append(buf);
    ++rows;
  }

  void write_steady(const Measures& m, double ca) {
    const auto& d = m.shape;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n",
                  cap->time(), ca, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.area, d.edge_curvature,
                  m.tau_max, m.tau_min);
    dir->steady().append(buf);
    ++steady_rows;
  }

  void write_profiles(long index) {
    std::ostringstream f;
    f << "plane,t,a,b\n";
    const diagnostics::ShapeDiagnostics d = measure(false).shape;
    const Eigen::Vector3d c = d.centroid;
    for (const auto& [plane, axis] : {std::pair<const char*, int>{"z", 2}, {"y", 1}}) {
      const Eigen::Vector2d center(c.x(), axis == 2 ? c.y() : c.z());
      for (const Eigen::Vector2d& p :
           diagnostics::cross_section(*mesh, cap->positions(), axis, c[axis], center)) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "%s,%.10g,%.10g,%.10g\n", plane, cap->time(), p.x(), p.y());
        f << buf;
      }
    }
    dir->subdirectory("profiles");
    char name[64];
    std::snprintf(name, sizeof name, "profiles/profile_%06ld.csv", index);
    dir->write_text(name, f.str());
  }

  void submit_frame(const Measures& m, double ca) {
    write_profiles(frames);
    if (!renderer) {
      ++frames;
      return;
    }
    render::Snapshot sn = snapshot(m, ca);
    sn.frame = frames;
    if (!renderer->submit_frame(std::move(sn)))
      throw OutputError("frames could not be written: " + renderer->error());
    ++frames;  // handed to the renderer
  }

  // The ParaView surface (app/surface_export.h: output.vtk_points per element edge, tensions,
  // mean curvature, the velocity of this state) + the .pvd collection entry.
  void write_vtk(const Measures& m, double ca) {
    dir->subdirectory("vtk");
    const std::string name = surface_file_name(vtk_index);
    as_output("cannot write " + dir->file(name).string(), [&] {
      if (!pvd)
        pvd = std::make_unique<output::PvdCollection>(dir->file(kSurfaceCollection).string());
      output::write_vtp(dir->file(name).string(), surface(m, ca));
      pvd->add(cap->time(), name);
    });
    ++vtk_index;
  }

  output::VtkSurface surface(const Measures& m, double ca) const {
    // one more velocity evaluation; the Krylov warm start (lambda != 1) is put back, so the run
    // goes on as it would without ParaView output
    const Eigen::VectorXd warm = cap->krylov_warm_start();
    const Eigen::Matrix3Xd u = cap->velocity(cap->positions(), ca);
    cap->set_krylov_warm_start(warm);
    const render::Snapshot sn = snapshot(m, ca);
    const Eigen::Matrix3Xd& x = cap->positions();
    const int n = opt.output.vtk_points > 0 ? opt.output.vtk_points : mesh->nb();
    return surface_export(*mesh, {&x, &u, &sn}, n);
  }

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
    s.frames = frames_on_disk();
    s.vtk_index = vtk_index;
    s.rows = rows;
    s.steady_rows = steady_rows;
    s.resumes = resumes;
    s.wall_s = wall();
    s.checkpoint_now_seen = checkpoint_now_seen;
    s.pending_row = pending.row;
    s.pending_frame = pending.frame;
    s.pending_vtk = pending.vtk;
    s.pending_steady_ca = pending_steady_ca;
    s.pending_ca = pending_ca;
    s.h_next = stepper->adaptive() ? stepper->next_step() : 0.0;
    if (stepper->adaptive()) s.step_history = stepper->history();
    s.krylov_warm = cap->krylov_warm_start();
    return s;
  }

  // Frames a checkpoint counts: those whose files are written (the renderer's queue is drained
  // first, write_checkpoint), so that a resume never leaves a gap in the frame numbers.
  long frames_on_disk() const {
    if (!renderer) return frames;
    const long through = renderer->frames_written_through();
    return through >= 0 ? through : session_first_frame;
  }

  // Movie frames handed to the renderer that it did not write (it failed with them in its
  // queue). A frame of this step that was not handed over is not among them: a checkpoint of
  // this state records it as due (pending.frame).
  long frames_lost_in_flight() const {
    if (!renderer) return 0;
    renderer->wait_idle();
    return std::max(0L, frames - frames_on_disk());
  }

  void write_checkpoint(const std::string& why) {
    if (renderer) renderer->wait_idle();
    // The rows, frames and movie fragments it counts on stable storage before it is: a disk that
    // fails (a journal abort, a power cut) never leaves a checkpoint counting what was lost.
    dir->sync();
    dir->subdirectory("checkpoints");
    const fs::path path = dir->checkpoint_path(cap->step_count());
    const RunCheckpoint state = checkpoint_state();
    write_run_checkpoint(state, path.string());
    dir->prune_checkpoints(3);
    event(Record()
              .set("event", "checkpoint")
              .set("file", path.string())
              .set("why", why)
              .set("steps", cap->step_count()));
    dir->log().append("[" + iso_now() + "] checkpoint " + path.string() + " (" + why + ")\n");
  }

  // ---- the four parts of a loop iteration ---------------------------------------------------

  // Applies a saved edit of the control file (step boundary) and run.checkpoint_now.
  void apply_edits() {
    const bool changed = watcher && (watcher->changed() || check_file_now);
    check_file_now = false;
    if (changed) apply_file_edit();
    if (opt.run.checkpoint_now && !checkpoint_now_seen) write_checkpoint("run.checkpoint_now");
    checkpoint_now_seen = opt.run.checkpoint_now;
  }

  // A continuation is capflow steady's: an edit of "ca" to one is refused, the rest applies.
  void refuse_continuation(control::EditResult* r) const {
    if (!r->schedule_changed || !r->merged.ca.continuation) return;
    r->merged.ca = opt.ca;
    r->schedule_changed = false;
    for (auto it = r->applied.begin(); it != r->applied.end(); ++it)
      if (it->path == "ca") {
        control::OptionChange c = *it;
        c.reason = control::kContinuationRefused;
        r->refused.push_back(c);
        r->applied.erase(it);
        break;
      }
  }

  void apply_file_edit() {
    control::ParsedControl edited;
    std::string text;
    try {
      text = control::read_control_text(control_source);
      edited = control::parse_control(text, control_source);
    } catch (const control::ControlError& e) {
      std::vector<std::string> errs;
      for (const auto& i : e.issues()) errs.push_back(i.str());
      const std::string what = e.what();
      say("refused edit of " + control_source + " (the run keeps its settings):\n  " +
          what.substr(what.find('\n') + 1));
      event(Record().set("event", "edit").set("accepted", false).set("errors", errs));
      apply_run_keys(control::run_keys_of(text));
      return;
    }
    control::EditResult r = control::apply_edit(opt, file_opt, edited.options);
    refuse_continuation(&r);
    file_opt = edited.options;
    if (r.applied.empty() && r.refused.empty()) return;  // saved without changes to the run
    const double now = t();
    const double ca_before = schedule->ca(now);
    const control::OutputOptions before = opt.output;
    opt = r.merged;
    cap->set_volume_correction(opt.numerics.volume_correction);
    stepper->configure(opt.time);
    if (r.steady_changed) schedule->set_steady(opt.steady);
    std::string schedule_note;
    if (r.schedule_changed) {
      schedule_note = schedule->edit(opt.ca, now);
      stepper->restart();  // Ca may jump here
    }
    std::string thread_cut;
    set_solver_threads(opt.numerics.threads, &thread_cut);
    cadence->edit(before, opt.output, now);
    write_effective_control();
    std::ostringstream m;
    m << "edit applied at t = " << now << ":";
    Record applied, refused;
    for (const auto& c : r.applied) {
      m << " " << c.path << " " << c.old_value << " -> " << c.new_value << ";";
      applied.set(c.path, control::change_record(c));
    }
    for (const auto& c : r.refused) {
      m << " refused " << c.path << " (" << c.reason << ");";
      refused.set(c.path, control::change_record(c, c.reason));
    }
    if (r.schedule_changed)
      m << " Ca " << ca_before << " -> " << schedule->ca(now) << " (" << schedule_note << ")";
    say(m.str());
    for (const auto& w : edited.warnings) say("warning: " + w.str());
    if (!thread_cut.empty()) warn("threads", thread_cut);
    event(Record()
              .set("event", "edit")
              .set("accepted", true)
              .set("applied", applied)
              .set("refused", refused)
              .set("ca", schedule->ca(now)));
  }

  // A stop, a pause or a checkpoint request is honoured even when the rest of its edit is refused.
  void apply_run_keys(const std::optional<control::RunOptions>& run) {
    if (!run) return;
    const control::RunOptions before = opt.run;
    if (run->state == file_opt.run.state && run->checkpoint_now == file_opt.run.checkpoint_now)
      return;  // the file's run keys did not change
    opt.run = *run;
    file_opt.run = *run;
    if (opt.run.state != before.state)
      say("run.state " + control::to_string(before.state) + " -> " +
          control::to_string(opt.run.state) + " applied (run keys are honoured alone)");
    write_effective_control();
  }

  // One step and the health check (on failure the last good state is kept). Adaptive steps
  // end at t_end, the next output time or the next change of the Ca schedule at the latest.
  StepOutcome advance() {
    const double breakpoint = schedule->next_breakpoint(t());
    const double t_stop = std::min({opt.time.t_end, cadence->next_time(), breakpoint});
    const TimeStepper::Outcome o = stepper->advance(
        t_stop, [&](double tt) { return schedule->ca(tt); }, *health);
    // An adaptive step that ended on the schedule's change: the schedule sees it now.
    at_breakpoint = stepper->adaptive() && o.failure.empty() && t() == breakpoint;
    for (const capsule::HealthReport& w : o.warnings) {
      say("warning: " + w.message);
      event(Record().set("event", "warning").set("cause", w.cause).set("message", w.message));
    }
    StepOutcome out;
    out.failure = o.failure;
    if (out.failure.empty()) last_dt = o.dt;
    rejected += o.rejected;
    return out;
  }

  // Diagnostics as the outputs due need them, and the Ca schedule's shape sample.
  Observation observe(const Due& due, double dt) {
    Observation ob;
    const double now = t();
    ob.ca = schedule->ca(now);
    const double eps = 1e-9 * dt;
    const bool sample = now >= next_sample - eps || at_breakpoint;
    if (!sample && !due.full_measure()) return ob;
    ob.m = measure(due.full_measure());
    ob.measured = true;
    if (sample) {
      // Shape samples for steady-state detection: about 20 per window.
      next_sample = now + std::min(opt.steady.window / 20.0, opt.output.csv_every) - eps;
      ob.schedule = schedule->sample(now, ob.m.shape.L, ob.m.shape.S, ob.m.shape.W);
      if (ob.schedule.steady && !due.full_measure()) ob.m = measure(true);
    }
    return ob;
  }

  // Writes the pending row, frame and surface of this step (each cleared once written).
  void write_due(const Measures& m, double ca) {
    if (pending.frame) {
      submit_frame(m, ca);
      pending.frame = false;
    }
    if (pending.vtk) {
      write_vtk(m, ca);
      pending.vtk = false;
    }
    if (pending.row) {
      write_row(m, ca);
      pending.row = false;
    }
  }

  // A resume after an output failure: what that step did not write, first.
  void write_pending() {
    if (!pending.full_measure() && std::isnan(pending_steady_ca)) return;
    const Measures m = measure(true);
    if (!std::isnan(pending_steady_ca)) {
      write_steady(m, pending_steady_ca);
      pending_steady_ca = NAN;
    }
    write_due(m, pending_ca);
    say("wrote the outputs of t = " + std::to_string(t()) + " that the output failure left out");
  }

  // Writes what is due at this step. Returns true when the run should stop at a steady state.
  bool emit(const Observation& ob, const Due& due) {
    const double now = t();
    const double ca = ob.ca;
    bool stop_here = false;
    const control::CaScheduler::Event& ev = ob.schedule;
    pending = due;
    pending.checkpoint = false;
    pending_ca = ca;
    pending_steady_ca = ev.steady ? ev.steady_ca : NAN;
    if (ev.steady) {
      write_steady(ob.m, ev.steady_ca);
      pending_steady_ca = NAN;
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
    write_due(ob.m, ca);
    if (due.full_measure()) {
      if (renderer && opt.render.preview) renderer->offer_preview(snapshot(ob.m, ca));
      const capsule::HealthReport w =
          health->check_wrinkling(now, ob.m.tau_min, ob.m.tau_min_at, schedule->max_rate());
      if (w.level == capsule::HealthLevel::Warning) {
        say("warning: " + w.message);
        event(Record().set("event", "warning").set("cause", w.cause).set("message", w.message));
      }
    }
    if (due.checkpoint) write_checkpoint("output.checkpoint_every");
    cadence->fired(due, opt.output, now);
    return stop_here;
  }

  void report_progress(Progress& progress, const Observation& ob, double D) {
    if (!progress.due()) return;
    const double now = t();
    const double rate = progress.rate(cap->step_count());
    const double eta = (opt.time.t_end - now) / std::max(progress.time_rate(now), 1e-12);
    const double eta_steady = schedule->eta_steady(now);
    std::ostringstream line;
    line << "t=" << fixed(now, 4) << " Ca=" << fixed(schedule->ca(now), 4)
         << " D=" << fixed(ob.measured ? ob.m.shape.D : D, 4) << " dt=" << std::setprecision(3)
         << last_dt << " " << fixed(rate, 1) << " steps/s, ETA " << fixed(eta, 0) << " s to t_end";
    if (eta_steady >= 0) line << ", steady in ~" << fixed(eta_steady, 2) << " (sim. time)";
    log->status(line.str());
  }

  // ---- the session --------------------------------------------------------------------------

  void announce(bool fresh) {
    const control::ControlOptions& o = opt;
    std::ostringstream m;
    m << "capflow run: " << membrane::to_string(o.law.kind) << ", " << o.flow.name()
      << ", NE=" << o.mesh.elements
      << (o.mesh.division == geometry::Division::Cube
              ? ""
              : std::string(" (") + control::division_name(o.mesh.division) + " division)")
      << " NB=" << o.mesh.nb << ", dt="
      << (o.time.adaptive ? "auto (tolerance " + fixed_or_sci(o.time.tolerance) + ")"
                          : fixed_or_sci(o.time.dt))
      << ", t_end=" << o.time.t_end << ", " << omp_get_max_threads() << " threads"
      << (parallel::size() > 1 ? " x " + std::to_string(parallel::size()) + " MPI ranks" : "")
      << ", kernels " << spectral::simd_width_name() << ", symmetry targets "
      << cap->symmetry().targets().size() << "/" << mesh->num_unique();
    if (o.numerics.quadrature_scale != 1.0)
      m << ", quadrature orders x" << o.numerics.quadrature_scale;
    m << " -> " << dir->path().string();
    if (watcher)
      m << "; watching " << control_source
        << (watcher->using_inotify() ? " (inotify)" : " (polling)");
    say(m.str());
    say("Ca schedule: " + schedule->describe(t()));
    if (fresh) event(Record().set("event", "start").set_json("control", control::to_json_text(o)));
    if (!thread_warning.empty()) warn("threads", thread_warning);
  }

  // A paused run: returns true while paused (logs the change once).
  bool paused(Progress& progress) {
    if (opt.run.state == control::RunState::Paused) {
      if (!paused_logged) {
        say("paused at t = " + std::to_string(t()) + " (set run.state to \"running\" to continue)");
        event(Record().set("event", "pause"));
        paused_logged = true;
        progress.pause();
      }
      return true;
    }
    if (paused_logged) {
      say("running again");
      event(Record().set("event", "continue"));
      paused_logged = false;
      progress.unpause();
    }
    return false;
  }

  // Runs `f`; an output failure inside it degrades the log (stderr only) instead of throwing.
  template <class F>
  void best_effort(F&& f) {
    try {
      f();
    } catch (const OutputError& e) {
      log->degrade();
      console::err(std::string("capflow: ") + e.what());
    }
  }
};

Simulation::Simulation() : impl_(std::make_unique<Impl>()) {}

Simulation::Simulation(const control::ControlOptions& options, const std::string& control_source)
    : Simulation(NewRun{options, options, control_source, false}) {}

Simulation::Simulation(const NewRun& run) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.opt = run.options;
  s.file_opt = run.file_options;
  s.control_source = run.control_source;
  const fs::path out = run.options.output.dir;
  // Everything that can be refused is checked before the run directory is touched.
  std::optional<RunCheckpoint> source;
  if (!run.options.start.from.empty()) {
    auto inside = [](const fs::path& p, const fs::path& d) {
      const std::string a = fs::weakly_canonical(fs::absolute(p)).string() + "/";
      const std::string b = fs::weakly_canonical(fs::absolute(d)).string() + "/";
      return a.compare(0, b.size(), b) == 0;
    };
    if (inside(run.options.start.from, out))
      throw UserError("start.from: " + run.options.start.from +
                      " is in this run's own directory (output.dir " + out.string() +
                      "), whose outputs a new run overwrites: give another run's directory, "
                      "or continue this run with --resume");
    try {
      source = read_latest_checkpoint(run.options.start.from);
    } catch (const UserError& e) {
      throw UserError(std::string("start.from: ") + e.what());
    }
    const std::vector<control::ControlIssue> ti = control::time_issues(s.opt.time, source->t);
    if (!ti.empty())
      throw UserError(ti[0].path + ": " + ti[0].message +
                      " (the run starts at the time of start.from)");
  }
  const std::optional<double> initial_ca =
      source ? std::optional<double>(source->ca) : std::nullopt;
  try {
    const control::CaScheduler probe(s.opt.ca, s.opt.steady, 0.0, initial_ca);
    (void)probe;
  } catch (const std::invalid_argument& e) {
    throw UserError(e.what());
  }
  s.dir = RunDirectory::open(
      out, run.overwrite ? RunDirectory::Mode::Overwrite : RunDirectory::Mode::Create);
  s.fresh_start = true;
  try {
    s.log = std::make_unique<RunLog>(*s.dir, isatty(STDERR_FILENO));
    s.dir->open_records(true, kTimeseriesHeader, kSteadyHeader);
    s.write_effective_control();
    s.dir->write_text(
        "control.source",
        (run.control_source.empty() ? "" : fs::absolute(run.control_source).string()) + "\n");
    s.build_solver();
    if (source) s.start_from(*source);
    s.start_monitors(initial_ca);
    s.checkpoint_now_seen = run.options.run.checkpoint_now;
    if (!run.control_source.empty())
      s.watcher = std::make_unique<control::FileWatcher>(run.control_source);
    s.start_renderer();
  } catch (...) {
    // A start that failed leaves nothing behind: the same command works once the cause is gone.
    s.abandon_start();
    throw;
  }
}

std::string Simulation::latest_checkpoint(const std::string& run_dir) {
  const std::vector<fs::path> all = RunDirectory::checkpoints(run_dir);
  return all.empty() ? "" : all.front().string();
}

namespace {

// A run written before timeseries.csv had its dt column: the column is inserted (empty) into the
// header and every row, so that the rows a resume appends line up with them.
void upgrade_timeseries(const RunDirectory& dir) {
  const fs::path path = dir.file("timeseries.csv");
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  std::string text;
  try {
    files::InputFile in(path.string(), "time series", figures::kMaxTableBytes);
    const std::string head = in.read_prefix(4096);
    const std::string header = head.substr(0, head.find('\n'));
    const std::string before = ",steps,wall_s";
    if (header.size() < before.size() ||
        header.compare(header.size() - before.size(), before.size(), before) != 0)
      return;
    text = in.read_all();
  } catch (const files::InputError& e) {
    throw UserError(e.what());
  }
  std::istringstream in(text);
  std::string header;
  std::getline(in, header);
  std::ostringstream out;
  out << header.substr(0, header.size() - 6) << "dt,wall_s\n";
  for (std::string line; std::getline(in, line);) {
    const size_t last = line.rfind(',');
    if (last == std::string::npos) continue;
    out << line.substr(0, last) << "," << line.substr(last) << "\n";
  }
  dir.write_text("timeseries.csv", out.str());
}

// The control file a resumed run watches again: control.source names it ("" when the run had
// none, or the file named is gone).
std::string watched_control(const RunDirectory& dir) {
  std::string text;
  try {
    text = files::read_input_file(dir.file("control.source").string(), "control.source",
                                  std::size_t{64} << 10);
  } catch (const files::InputError&) {
    return "";
  }
  const std::string line = text.substr(0, text.find('\n'));
  std::error_code ec;
  return !line.empty() && fs::exists(line, ec) ? line : "";
}

// A checkpoint a resume can continue from: its rows are all whole lines of the CSV files (a
// torn last line - a crash mid-write - is cut off, and an older checkpoint taken when a recorded
// row is torn).
CheckpointFits rows_on_disk(const RunDirectory& dir) {
  const AppendFile::Lines ts = AppendFile::count_lines(dir.file("timeseries.csv"));
  const AppendFile::Lines st = AppendFile::count_lines(dir.file("steady.csv"));
  return [ts, st](const RunCheckpoint& c) -> std::string {
    if (c.rows + 1 > ts.whole)
      return "it recorded " + std::to_string(c.rows) + " rows of timeseries.csv, which holds " +
             std::to_string(std::max(0L, ts.whole - 1)) + " whole rows" +
             (ts.torn ? " and a torn one" : "");
    if (c.steady_rows + 1 > st.whole)
      return "it recorded " + std::to_string(c.steady_rows) + " rows of steady.csv, which holds " +
             std::to_string(std::max(0L, st.whole - 1)) + " whole rows" +
             (st.torn ? " and a torn one" : "");
    return "";
  };
}

}  // namespace

std::unique_ptr<Simulation> Simulation::resume(const std::string& run_dir,
                                               const ResumeOverrides& ov) {
  std::unique_ptr<Simulation> sim(new Simulation());
  Impl& s = *sim->impl_;
  s.dir = RunDirectory::open(run_dir, RunDirectory::Mode::Resume);
  std::vector<std::string> skipped;
  upgrade_timeseries(*s.dir);
  const RunCheckpoint c = read_latest_checkpoint(run_dir, &skipped, rows_on_disk(*s.dir));
  s.opt = c.options;
  if (ov.t_end) s.opt.time.t_end = *ov.t_end;
  const std::vector<control::ControlIssue> ti = control::time_issues(s.opt.time, c.t);
  if (!ti.empty())
    throw UserError(std::string(ov.t_end ? "--t-end" : "time.t_end") + ": " + ti[0].message +
                    (ov.t_end ? "" : "; give --t-end to run on"));
  s.opt.output.dir = run_dir;
  s.opt.run.state = control::RunState::Running;
  try {
    s.file_opt = control::parse_control(c.control_file, c.path + " (stored control file)").options;
  } catch (const control::ControlError&) {
    s.file_opt = c.options;
  }
  // What a torn last line held is kept beside the file (e.g. timeseries.csv.torn).
  s.dir->timeseries().open(s.dir->file("timeseries.csv"), false);
  s.dir->timeseries().keep_lines(c.rows + 1, s.dir->file("timeseries.csv.torn"));
  s.dir->steady().open(s.dir->file("steady.csv"), false);
  s.dir->steady().keep_lines(c.steady_rows + 1, s.dir->file("steady.csv.torn"));
  s.dir->open_records(false, kTimeseriesHeader, kSteadyHeader);
  s.log = std::make_unique<RunLog>(*s.dir, isatty(STDERR_FILENO));
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
  s.frames = s.session_first_frame = c.frames;
  s.vtk_index = c.vtk_index;
  remove_outputs_after(*s.dir, c.frames);
  s.rows = c.rows;
  s.steady_rows = c.steady_rows;
  s.resumes = c.resumes + 1;
  s.wall_offset = c.wall_s;
  s.checkpoint_now_seen = c.checkpoint_now_seen;
  s.pending.row = c.pending_row;
  s.pending.frame = c.pending_frame;
  s.pending.vtk = c.pending_vtk;
  s.pending_steady_ca = c.pending_steady_ca;
  s.pending_ca = c.pending_ca;
  if (fs::exists(s.dir->file(kSurfaceCollection)))
    as_output("cannot rewrite " + s.dir->file(kSurfaceCollection).string(), [&] {
      s.pvd = std::make_unique<output::PvdCollection>(s.dir->file(kSurfaceCollection).string());
      s.pvd->truncate_after(c.t);
    });
  s.write_effective_control();
  if (const std::string watched = watched_control(*s.dir); !watched.empty()) {
    s.control_source = watched;
    s.watcher = std::make_unique<control::FileWatcher>(watched);
    s.check_file_now = true;
  }
  for (const std::string& why : skipped)
    s.say("warning: skipped a checkpoint that does not read: " + why);
  s.event(Record()
              .set("event", "resume")
              .set("checkpoint", c.path)
              .set("steps", s.cap->step_count())
              .set("skipped", skipped));
  s.say("resuming " + run_dir + " from " + c.path + " at t = " + std::to_string(s.cap->time()));
  s.start_renderer();
  return sim;
}

Simulation::~Simulation() {
  if (impl_ && impl_->renderer) impl_->renderer->stop();
}

RunSummary Simulation::run(const std::atomic<bool>* stop) {
  Impl& s = *impl_;
  s.start = std::chrono::steady_clock::now();
  Progress progress(s.log->tty());
  progress.start(s.cap->step_count(), s.t());
  RunSummary sum;
  const bool fresh = s.cap->step_count() == 0 && s.rows == 0;
  std::string reason = "t_end reached";
  Observation last;
  try {
    s.announce(fresh);
    last.m = s.measure(true);
    last.measured = true;
    if (fresh) {
      s.pending.row = true;
      s.pending.frame = s.opt.output.frame_every > 0;
      s.pending.vtk = s.opt.output.vtk_every > 0;
      s.pending_ca = s.schedule->ca(s.t());
      // The checkpoint first: it records the outputs of t = 0 as due, and no frame is in flight.
      s.write_checkpoint("start");
      s.write_due(last.m, s.pending_ca);
    } else {
      s.write_pending();
    }
    for (;;) {
      s.apply_edits();
      if (stop && stop->load()) {
        reason = "stopped by signal";
        break;
      }
      if (s.opt.run.state == control::RunState::Stopped) {
        reason = "run.state is \"stopped\"";
        break;
      }
      if (s.paused(progress)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      if (s.stepper->done(s.opt.time.t_end)) break;
      const StepOutcome step = s.advance();
      if (!step.failure.empty()) {
        sum.failed = true;
        sum.failure = step.failure;
        s.say("failure: " + step.failure +
              " (keeping the last good state, t = " + std::to_string(s.t()) + ")");
        s.event(Record().set("event", "failure").set("message", step.failure));
        reason = "failure";
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
        reason = "steady state of the final level (steady.stop)";
        break;
      }
    }
    s.write_checkpoint(reason);
    if (s.renderer) {
      const render::RenderStats rs = s.renderer->stop();
      std::ostringstream r;
      r << "renderer: " << rs.movie_frames << " movie frames written, solver waited "
        << rs.producer_waits << " times for the renderer";
      if (rs.movie_frames > 0) {
        const double n = static_cast<double>(rs.movie_frames);
        char b[200];
        std::snprintf(b, sizeof b,
                      "; ms per frame: upsample %.1f, draw %.1f, overlay %.1f, readback %.1f, "
                      "PNG %.1f, encode %.1f",
                      rs.total.upsample_ms / n, rs.total.draw_ms / n, rs.total.overlay_ms / n,
                      rs.total.readback_ms / n, rs.png_ms / n, rs.encode_ms / n);
        r << b;
      }
      const std::string err = s.renderer->error();
      s.renderer.reset();
      s.say(r.str());
      if (!err.empty()) throw OutputError("frames could not be written: " + err);
    }
  } catch (const OutputError& e) {
    sum.output_failed = true;
    sum.failure = e.what();
    reason = "output failure";
    s.best_effort([&] { s.say(std::string("output failure: ") + e.what()); });
    s.best_effort([&] {
      s.event(Record().set("event", "failure").set("message", e.what()).set("cause", "output"));
    });
    // The state is good: keep it if the disk still takes a checkpoint; otherwise the last one
    // written stays the one to resume from.
    std::string kept = Simulation::latest_checkpoint(s.dir->path().string());
    const long lost = s.frames_lost_in_flight();
    if (lost > 0) {
      // Frames of earlier states were in the renderer's queue when it failed: a checkpoint of
      // this state would skip their times. The last checkpoint stays the one to resume from, and
      // the resume makes them again.
      s.best_effort([&] {
        s.say(std::to_string(lost) + " frame(s) in the renderer's queue were not written: no " +
              "checkpoint of this state (a resume makes them again from the last one)");
      });
    } else {
      try {
        s.write_checkpoint("output failure");
        kept = Simulation::latest_checkpoint(s.dir->path().string());
      } catch (const OutputError& e2) {
        s.best_effort([&] { s.say(std::string("final checkpoint not written: ") + e2.what()); });
      }
    }
    if (kept.empty() && s.fresh_start) {
      // No checkpoint was ever written: the start failed. Nothing is left behind.
      console::err("capflow: the run could not start (" + std::string(e.what()) +
                   "); removed what it had written in " + s.dir->path().string());
      s.abandon_start();
      sum.output_failed = true;
      sum.failure = e.what();
      sum.reason = "output failure";
      return sum;
    }
    s.best_effort([&] {
      s.say(kept.empty() ? "no checkpoint to resume from"
                         : "resume with: capflow run --resume " + s.dir->path().string() +
                               " (from " + kept + ")");
    });
    if (s.renderer) {
      s.renderer->stop();
      s.renderer.reset();
    }
  }
  const Measures m = s.measure(true);
  sum.reason = reason;
  sum.t = s.t();
  sum.steps = s.cap->step_count();
  sum.evaluations = s.cap->velocity_evaluations();
  sum.krylov_iterations = s.cap->krylov_iterations();
  sum.wall_s = s.wall();
  sum.D = m.shape.D;
  sum.L = m.shape.L;
  sum.S = m.shape.S;
  sum.W = m.shape.W;
  sum.volume_drift = m.shape.volume / s.cap->initial_volume() - 1.0;
  std::ostringstream fin;
  fin << "end (" << reason << "): t=" << sum.t << " steps=" << sum.steps << " (rejected "
      << s.rejected << ") velocity evaluations=" << sum.evaluations;
  if (s.opt.viscosity_ratio != 1.0)
    fin << " (GMRES iterations " << sum.krylov_iterations << ", " << std::setprecision(3)
        << static_cast<double>(sum.krylov_iterations) / std::max<long>(1, sum.evaluations)
        << " per evaluation)";
  fin << " wall=" << std::fixed << std::setprecision(1) << sum.wall_s
      << " s, D=" << std::setprecision(5) << sum.D << " L=" << sum.L << " S=" << sum.S
      << " W=" << sum.W << ", volume drift " << std::scientific << std::setprecision(2)
      << sum.volume_drift << ", steady states " << s.steady_rows;
  s.best_effort([&] { s.say(fin.str()); });
  s.best_effort([&] {
    s.event(Record()
                .set("event", "end")
                .set("reason", reason)
                .set("exit_code", sum.exit_code())
                .set("steps", sum.steps)
                .set("velocity_evaluations", sum.evaluations)
                .set("rejected_steps", s.rejected)
                .set("D", sum.D)
                .set("L", sum.L)
                .set("S", sum.S)
                .set("W", sum.W)
                .set("volume_drift", sum.volume_drift)
                .set("wall_s", sum.wall_s));
  });
  return sum;
}

}  // namespace capflow::app
