#include "app/simulation.h"

#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "capsule/capsule.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "control/schedule.h"
#include "diagnostics/diagnostics.h"
#include "membrane/membrane.h"
#include "render/render_thread.h"
#include "render/snapshot.h"

namespace capflow::app {

namespace fs = std::filesystem;

namespace {

std::string iso_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

struct Measures {
  diagnostics::ShapeDiagnostics shape;
  double tau_max = 0, tau_min = 0;
  Eigen::Vector3d tau_min_at = Eigen::Vector3d::Zero();
};

}  // namespace

struct Simulation::Impl {
  control::ControlOptions opt;
  fs::path dir;
  std::ofstream timeseries, steady, events, log;
  std::unique_ptr<geometry::Mesh> mesh;
  std::unique_ptr<capsule::Capsule> cap;
  std::unique_ptr<capsule::HealthMonitor> health;
  std::unique_ptr<control::CaScheduler> schedule;
  std::unique_ptr<render::RenderThread> renderer;
  long frames = 0;
  std::chrono::steady_clock::time_point start;
  bool tty = false;

  double wall() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void say(const std::string& line) {
    if (tty) std::cerr << "\r\033[K";
    std::cerr << line << std::endl;
    log << "[" << iso_now() << "] " << line << std::endl;
  }

  void event(nlohmann::json e) {
    e["wall_time"] = iso_now();
    if (cap) e["t"] = cap->time();
    events << e.dump() << "\n";
    events.flush();
  }

  Measures measure(bool full) {
    Measures m;
    diagnostics::ShapeOptions so;
    so.axes = opt.flow.type == capsule::FlowType::SimpleShear ? diagnostics::AxesMode::Shear
                                                               : diagnostics::AxesMode::FlowAxes;
    so.extrema = full;
    so.edge_curvature = full;
    m.shape = diagnostics::measure_shape(*mesh, cap->positions(), so);
    if (full) {
      const membrane::MembraneFields f = cap->membrane().fields(cap->positions());
      Eigen::Index imax, imin;
      m.tau_max = f.tension1.maxCoeff(&imax);
      m.tau_min = f.tension2.minCoeff(&imin);
      m.tau_min_at = cap->positions().col(imin);
    }
    return m;
  }

  render::Snapshot snapshot(const Measures& m, double ca) {
    render::Snapshot sn;
    sn.ne = mesh->ne();
    sn.nb = mesh->nb();
    const Eigen::Matrix3Xd& x = cap->positions();
    sn.x.assign(x.data(), x.data() + x.size());
    const membrane::MembraneFields f = cap->membrane().fields(x);
    sn.tau1.assign(f.tension1.data(), f.tension1.data() + f.tension1.size());
    sn.tau2.assign(f.tension2.data(), f.tension2.data() + f.tension2.size());
    sn.time = cap->time();
    sn.ca = ca;
    sn.law = membrane::to_string(opt.law.kind);
    sn.diag = {m.shape.D, m.shape.L, m.shape.S, m.shape.W, m.tau_max, m.tau_min};
    return sn;
  }

  void submit_frame(const Measures& m, double ca) {
    if (!renderer) return;
    render::Snapshot sn = snapshot(m, ca);
    sn.frame = frames++;
    if (!renderer->submit_frame(std::move(sn))) {
      say("renderer stopped: " + renderer->error() + "; frames are no longer written");
      event({{"event", "warning"}, {"cause", "renderer"}, {"message", renderer->error()}});
      renderer->stop();
      renderer.reset();
    }
  }

  void write_row(const Measures& m, double ca) {
    const auto& d = m.shape;
    char buf[640];
    std::snprintf(buf, sizeof buf,
                  "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.12g,%.10g,%.10g,"
                  "%.10g,%.8g,%.6e,%ld,%.3f\n",
                  cap->time(), ca, d.D, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.area, d.volume,
                  d.edge_curvature, m.tau_max, m.tau_min, d.inclination_deg,
                  d.volume / cap->initial_volume() - 1.0, cap->step_count(), wall());
    timeseries << buf;
    timeseries.flush();
  }

  void write_steady(const Measures& m, double ca) {
    const auto& d = m.shape;
    char buf[512];
    std::snprintf(buf, sizeof buf, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n",
                  ca, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.area, d.edge_curvature, m.tau_max,
                  m.tau_min);
    steady << buf;
    steady.flush();
  }
};

Simulation::Simulation(const control::ControlOptions& options) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.opt = options;
  s.dir = options.output.dir;
  std::error_code ec;
  fs::create_directories(s.dir, ec);
  if (ec) throw std::runtime_error("cannot create the run directory " + s.dir.string() + ": " + ec.message());
  auto open = [&](std::ofstream& f, const char* name, std::ios::openmode mode) {
    f.open(s.dir / name, mode);
    if (!f) throw std::runtime_error("cannot write " + (s.dir / name).string());
  };
  {
    std::ofstream c;
    open(c, "control.json", std::ios::out | std::ios::trunc);
    c << control::to_json_text(options);
  }
  open(s.timeseries, "timeseries.csv", std::ios::out | std::ios::trunc);
  s.timeseries << "t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,"
                  "inclination_deg,volume_drift,steps,wall_s\n";
  open(s.steady, "steady.csv", std::ios::out | std::ios::trunc);
  s.steady << "ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min\n";
  open(s.events, "events.jsonl", std::ios::out | std::ios::trunc);
  open(s.log, "run.log", std::ios::out | std::ios::trunc);
  s.tty = isatty(STDERR_FILENO);

  if (options.numerics.threads > 0) omp_set_num_threads(options.numerics.threads);
  s.mesh = std::make_unique<geometry::Mesh>(options.mesh.elements, options.mesh.nb);
  capsule::DynamicsOptions d;
  d.viscosity_ratio = options.viscosity_ratio;
  d.smooth_geometry = d.smooth_traction = options.numerics.smoothing;
  d.volume_correction = options.numerics.volume_correction;
  d.symmetry = options.numerics.symmetry ? capsule::SymmetryChoice::Auto : capsule::SymmetryChoice::None;
  s.cap = std::make_unique<capsule::Capsule>(*s.mesh, options.law, options.flow, d);
  s.health = std::make_unique<capsule::HealthMonitor>(*s.mesh, s.cap->positions());
  s.schedule = std::make_unique<control::CaScheduler>(options.ca, options.steady, 0.0);
  const bool frames = options.output.frame_every > 0 && (options.output.png || options.output.mp4.enabled);
  if (frames || options.render.preview) {
    render::RenderOptions ro = options.render;
    ro.png = frames && options.output.png;
    ro.png_dir = (s.dir / "frames").string();
    ro.mp4 = frames && options.output.mp4.enabled;
    ro.mp4_path = (s.dir / "movie.mp4").string();
    ro.fps = options.output.mp4.fps;
    ro.crf = options.output.mp4.quality;
    ro.preview_path = (s.dir / "preview.png").string();
    if (ro.png) fs::create_directories(ro.png_dir);
    std::string err;
    if (!ro.IsValid(&err)) throw std::runtime_error("render options: " + err);
    s.renderer = std::make_unique<render::RenderThread>();
    s.renderer->start(ro, [&s](const std::string& line) { s.say(line); });
  }
}

Simulation::~Simulation() = default;

RunSummary Simulation::run(const std::atomic<bool>* stop) {
  Impl& s = *impl_;
  const control::ControlOptions& o = s.opt;
  s.start = std::chrono::steady_clock::now();
  RunSummary sum;
  const double dt = o.time.dt;
  const long total_steps = static_cast<long>(std::llround(o.time.t_end / dt));
  const long csv_stride = std::max(1L, static_cast<long>(std::llround(o.output.csv_every / dt)));
  // Shape samples for steady-state detection: at least 20 per window.
  const long steady_stride =
      std::max(1L, std::min(csv_stride, static_cast<long>(std::floor(o.steady.window / (20 * dt)))));

  {
    std::ostringstream m;
    m << "capflow run: " << membrane::to_string(o.law.kind) << ", " << o.flow.name() << ", NE="
      << o.mesh.elements << " NB=" << o.mesh.nb << ", dt=" << dt << ", t_end=" << o.time.t_end
      << ", " << omp_get_max_threads() << " threads, symmetry targets "
      << s.cap->symmetry().targets().size() << "/" << s.mesh->num_unique() << " -> "
      << s.dir.string();
    s.say(m.str());
    s.event({{"event", "start"}, {"control", nlohmann::json::parse(control::to_json_text(o))}});
  }
  Measures m = s.measure(true);
  s.write_row(m, s.schedule->ca(0.0));
  const long frame_stride =
      o.output.frame_every > 0 ? std::max(1L, static_cast<long>(std::llround(o.output.frame_every / dt))) : 0;
  s.submit_frame(m, s.schedule->ca(0.0));

  double last_status = -1;
  std::string stop_reason = "t_end reached";
  while (s.cap->step_count() < total_steps) {
    if (stop && stop->load()) {
      stop_reason = "stopped by signal";
      break;
    }
    if (o.run.state == control::RunState::Stopped) {
      stop_reason = "run.state is \"stopped\"";
      break;
    }
    const Eigen::Matrix3Xd last_good = s.cap->positions();
    const double t_prev = s.cap->time();
    const long steps_prev = s.cap->step_count();
    std::string failure;
    try {
      s.cap->step(dt, [&](double t) { return s.schedule->ca(t); });
    } catch (const std::exception& e) {
      failure = std::string("the step from t = ") + std::to_string(t_prev) + " failed: " + e.what();
    }
    if (failure.empty()) {
      const capsule::HealthReport h = s.health->check(s.cap->positions(), s.cap->time());
      if (h.level == capsule::HealthLevel::Failure) failure = h.message;
      if (h.level == capsule::HealthLevel::Warning) {
        s.say("warning: " + h.message);
        s.event({{"event", "warning"}, {"cause", h.cause}, {"message", h.message}});
      }
    }
    if (!failure.empty()) {
      s.cap->set_state(last_good, t_prev, steps_prev);
      sum.failed = true;
      sum.failure = failure;
      s.say("failure: " + failure + " (keeping the last good state, t = " + std::to_string(t_prev) + ")");
      s.event({{"event", "failure"}, {"message", failure}});
      stop_reason = "failure";
      break;
    }
    const long n = s.cap->step_count();
    const double t = s.cap->time();
    const bool frame = frame_stride > 0 && n % frame_stride == 0;
    const bool csv = n % csv_stride == 0 || n == total_steps || frame;
    if (csv || n % steady_stride == 0) {
      m = s.measure(csv);
      if (frame) s.submit_frame(m, s.schedule->ca(t));
      if (csv && s.renderer && o.render.preview) s.renderer->offer_preview(s.snapshot(m, s.schedule->ca(t)));
      const control::CaScheduler::Event ev =
          s.schedule->sample(t, m.shape.L, m.shape.S, m.shape.W);
      if (ev.steady) {
        if (!csv) m = s.measure(true);
        s.write_steady(m, s.cap->time() > 0 ? s.schedule->level() : 0.0);
        ++sum.steady_states;
      }
      if (ev.steady || ev.level_changed) {
        s.say(ev.description);
        s.event({{"event", ev.steady ? "steady" : "level"}, {"message", ev.description},
                 {"ca", s.schedule->ca(t)}, {"D", m.shape.D}, {"L", m.shape.L}});
      }
      if (csv) {
        if (n % csv_stride == 0 || n == total_steps) s.write_row(m, s.schedule->ca(t));
        const capsule::HealthReport w =
            s.health->check_wrinkling(t, m.tau_min, m.tau_min_at, s.schedule->max_rate());
        if (w.level == capsule::HealthLevel::Warning) {
          s.say("warning: " + w.message);
          s.event({{"event", "warning"}, {"cause", w.cause}, {"message", w.message}});
        }
      }
    }
    // Progress: at most once per second on a terminal, every 10 s otherwise.
    const double wall = s.wall();
    if (wall - last_status >= (s.tty ? 1.0 : 10.0)) {
      last_status = wall;
      const double sps = n / std::max(wall, 1e-9);
      const double eta = (total_steps - n) / std::max(sps, 1e-9);
      const double eta_steady = s.schedule->eta_steady(t);
      std::ostringstream line;
      line << std::fixed << std::setprecision(4) << "t=" << t << " Ca=" << s.schedule->ca(t)
           << " D=" << m.shape.D << " " << std::setprecision(1) << sps << " steps/s, ETA "
           << std::setprecision(0) << eta << " s to t_end";
      if (eta_steady >= 0) line << std::setprecision(2) << ", ~" << eta_steady << " to steady";
      if (s.tty)
        std::cerr << "\r\033[K" << line.str() << std::flush;
      else
        s.say(line.str());
    }
  }
  m = s.measure(true);
  if (s.cap->step_count() % csv_stride != 0) s.write_row(m, s.schedule->ca(s.cap->time()));
  if (s.renderer) {
    const render::RenderStats rs = s.renderer->stop();
    std::ostringstream r;
    r << "renderer: " << rs.movie_frames << " movie frames written";
    if (o.output.mp4.enabled && frame_stride > 0) r << " (movie.mp4)";
    r << ", solver waited " << rs.producer_waits << " times for the renderer";
    if (!s.renderer->error().empty()) r << "; error: " << s.renderer->error();
    s.say(r.str());
    s.renderer.reset();
  }
  sum.t = s.cap->time();
  sum.steps = s.cap->step_count();
  sum.wall_s = s.wall();
  sum.D = m.shape.D;
  sum.L = m.shape.L;
  sum.S = m.shape.S;
  sum.W = m.shape.W;
  sum.volume_drift = m.shape.volume / s.cap->initial_volume() - 1.0;
  std::ostringstream fin;
  fin << "end (" << stop_reason << "): t=" << sum.t << " steps=" << sum.steps << " wall=" << std::fixed
      << std::setprecision(1) << sum.wall_s << " s, D=" << std::setprecision(5) << sum.D
      << " L=" << sum.L << " S=" << sum.S << " W=" << sum.W << ", volume drift "
      << std::scientific << std::setprecision(2) << sum.volume_drift << ", steady states "
      << sum.steady_states;
  s.say(fin.str());
  s.event({{"event", "end"}, {"reason", stop_reason}, {"steps", sum.steps}, {"D", sum.D},
           {"L", sum.L}, {"S", sum.S}, {"W", sum.W}, {"volume_drift", sum.volume_drift},
           {"wall_s", sum.wall_s}});
  return sum;
}

}  // namespace capflow::app
