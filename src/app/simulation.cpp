#include "app/simulation.h"

#include "app/figure_data.h"
#include "output/vtk.h"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
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
#include <thread>

#include "capsule/capsule.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "control/edit.h"
#include "control/schedule.h"
#include "control/watcher.h"
#include "diagnostics/diagnostics.h"
#include "geometry/surface.h"
#include "membrane/membrane.h"
#include "output/checkpoint.h"
#include "render/render_thread.h"
#include "render/snapshot.h"

namespace capflow::app {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string iso_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

// The element division a checkpoint was written with (checkpoints before mesh.division have
// none: the cube).
geometry::Division checkpoint_division(const output::Checkpoint& c, const std::string& path) {
  if (!c.has("division")) return geometry::Division::Cube;
  const int64_t d = c.integer("division");
  if (d < 0 || d > 2)
    throw std::runtime_error(path + ": invalid element division " + std::to_string(d) +
                             " in the checkpoint (0 cube, 1 box, 2 diagonal)");
  return static_cast<geometry::Division>(d);
}

struct Measures {
  diagnostics::ShapeDiagnostics shape;
  double tau_max = 0, tau_min = 0;
  Eigen::Vector3d tau_min_at = Eigen::Vector3d::Zero();
};

// First multiple of `every` strictly after t (with a relative guard against round-off).
double next_after(double t, double every) {
  return every > 0 ? (std::floor(t / every + 1e-9) + 1.0) * every : INFINITY;
}

// Keeps the header and the first `rows` data lines of a CSV file.
void truncate_csv(const fs::path& p, long rows) {
  std::ifstream in(p);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::string line, out;
  long n = -1;
  while (n < rows && std::getline(in, line)) {
    out += line + "\n";
    ++n;
  }
  in.close();
  std::ofstream o(p, std::ios::trunc);
  o << out;
}

}  // namespace

struct Simulation::Impl {
  control::ControlOptions opt;
  fs::path dir;
  std::string control_source;
  std::unique_ptr<control::FileWatcher> watcher;
  std::ofstream timeseries, steady, events, log;
  std::unique_ptr<geometry::Mesh> mesh;
  std::unique_ptr<capsule::Capsule> cap;
  std::unique_ptr<capsule::HealthMonitor> health;
  std::unique_ptr<control::CaScheduler> schedule;
  std::unique_ptr<render::RenderThread> renderer;
  std::unique_ptr<output::PvdCollection> pvd;
  long frames = 0, rows = 0, steady_rows = 0, resumes = 0, vtk_index = 0;
  bool checkpoint_now_seen = false;
  std::chrono::steady_clock::time_point start;
  double wall_offset = 0;  // wall seconds of earlier sessions of this run
  bool tty = false;

  double wall() const {
    return wall_offset +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void say(const std::string& line) {
    if (tty) std::cerr << "\r\033[K";
    std::cerr << line << std::endl;
    log << "[" << iso_now() << "] " << line << std::endl;
  }

  void event(json e) {
    e["wall_time"] = iso_now();
    if (cap) e["t"] = cap->time();
    events << e.dump() << "\n";
    events.flush();
  }

  void open_files(bool append) {
    const auto mode = append ? std::ios::out | std::ios::app : std::ios::out | std::ios::trunc;
    auto open = [&](std::ofstream& f, const char* name) {
      f.open(dir / name, mode);
      if (!f) throw std::runtime_error("cannot write " + (dir / name).string());
    };
    open(timeseries, "timeseries.csv");
    open(steady, "steady.csv");
    open(events, "events.jsonl");
    open(log, "run.log");
    if (!append) {
      timeseries << "t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,"
                    "inclination_deg,volume_drift,steps,wall_s\n";
      steady << "ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min\n";
    }
    tty = isatty(STDERR_FILENO);
  }

  void write_effective_control() {
    const fs::path tmp = dir / "control.json.tmp";
    {
      std::ofstream c(tmp, std::ios::trunc);
      c << control::to_json_text(opt);
      if (!c) throw std::runtime_error("cannot write " + tmp.string());
    }
    fs::rename(tmp, dir / "control.json");
  }

  // The mesh, the capsule (at rest, or from `start`: see start_from), and the health monitor and
  // Ca schedule for that initial state (a resume restores their saved state afterwards).
  void build_solver(const control::StartOptions* start = nullptr) {
    if (opt.numerics.threads > 0) omp_set_num_threads(opt.numerics.threads);
    mesh = control::make_mesh(opt.mesh);
    cap = std::make_unique<capsule::Capsule>(*mesh, opt.law, opt.flow, control::dynamics_options(opt));
    if (start) start_from(*start);
    health = std::make_unique<capsule::HealthMonitor>(*mesh, cap->positions());
    schedule = std::make_unique<control::CaScheduler>(opt.ca, opt.steady, cap->time());
  }

  // "start.from": the newest checkpoint of a run directory (or a .ckpt file), its shape resampled
  // onto this run's mesh; time goes on from the checkpoint's t (build_solver starts the Ca
  // schedule there).
  void start_from(const control::StartOptions& st) {
    const std::string where = "start.from: " + st.from;
    std::string ckpt = st.from;
    if (fs::is_directory(st.from)) {
      ckpt = latest_checkpoint(st.from);
      if (ckpt.empty())
        throw std::runtime_error(where + " has no checkpoint in checkpoints/ (give a run directory "
                                 "with a checkpoint, or a .ckpt file)");
    } else if (!fs::is_regular_file(st.from)) {
      throw std::runtime_error(where + ": no such run directory or checkpoint file");
    }
    const output::Checkpoint c = output::Checkpoint::read(ckpt);  // names the file on error
    std::unique_ptr<geometry::Mesh> source;
    try {
      source = control::make_mesh({static_cast<int>(c.integer("elements")),
                                   static_cast<int>(c.integer("nb")), checkpoint_division(c, ckpt)});
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(ckpt + ": invalid mesh in the checkpoint (" + e.what() + ")");
    }
    const long n = source->num_local();
    const auto& xs = c.doubles("x", 3 * n);
    const double t0 = c.scalar("t");
    if (!std::isfinite(t0) || t0 < 0) throw std::runtime_error(ckpt + ": invalid time t in the checkpoint");
    Eigen::Matrix3Xd x =
        geometry::resample_surface(*source, Eigen::Map<const Eigen::Matrix3Xd>(xs.data(), 3, n), *mesh);
    if (!x.allFinite()) throw std::runtime_error(ckpt + ": the stored shape is not finite");
    const double drift_before = capsule::enclosed_volume(*mesh, x) / cap->initial_volume() - 1.0;
    if (st.restore_volume) x = capsule::rescale_to_volume(*mesh, x, cap->initial_volume());
    cap->set_state(x, t0, 0);
    std::ostringstream m;
    m << "initial shape from " << ckpt << " (NE=" << source->ne() << " NB=" << source->nb()
      << ", t = " << t0 << ") resampled onto NE=" << mesh->ne() << " NB=" << mesh->nb()
      << "; its volume drift " << drift_before
      << (st.restore_volume ? " was removed (start.restore_volume)" : " is kept");
    say(m.str());
    event({{"event", "start_from"}, {"checkpoint", ckpt}, {"source_elements", source->ne()},
           {"source_nb", source->nb()}, {"volume_drift_before", drift_before},
           {"restore_volume", st.restore_volume}});
  }

  void start_renderer() {
    const bool want_frames =
        opt.output.frame_every > 0 && (opt.output.png || opt.output.mp4.enabled);
    if (!want_frames && !opt.render.preview) return;
    render::RenderOptions ro = opt.render;
    ro.png = want_frames && opt.output.png;
    ro.png_dir = (dir / "frames").string();
    ro.mp4 = want_frames && opt.output.mp4.enabled;
    ro.mp4_path = (dir / (resumes == 0 ? std::string("movie.mp4")
                                       : "movie.part" + std::to_string(resumes + 1) + ".mp4"))
                      .string();
    ro.fps = opt.output.mp4.fps;
    ro.crf = opt.output.mp4.quality;
    ro.preview_path = (dir / "preview.png").string();
    if (ro.png) fs::create_directories(ro.png_dir);
    std::string err;
    if (!ro.IsValid(&err)) throw std::runtime_error("render options: " + err);
    renderer = std::make_unique<render::RenderThread>();
    renderer->start(ro, [this](const std::string& line) { say(line); });
  }

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
    render::Snapshot sn;
    sn.ne = mesh->ne();
    sn.nb = mesh->nb();
    const Eigen::Matrix3Xd& x = cap->positions();
    sn.x.assign(x.data(), x.data() + x.size());
    const membrane::MembraneFields f = cap->fields(x);
    sn.tau1.assign(f.tension1.data(), f.tension1.data() + f.tension1.size());
    sn.tau2.assign(f.tension2.data(), f.tension2.data() + f.tension2.size());
    sn.time = cap->time();
    sn.ca = ca;
    sn.law = membrane::to_string(opt.law.kind);
    sn.diag = {m.shape.D, m.shape.L, m.shape.S, m.shape.W, m.tau_max, m.tau_min};
    return sn;
  }

  void write_profiles(long index) {
    const fs::path pdir = dir / "profiles";
    fs::create_directories(pdir);
    char name[64];
    std::snprintf(name, sizeof name, "profile_%06ld.csv", index);
    std::ofstream f(pdir / name, std::ios::trunc);
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
  }

  void submit_frame(const Measures& m, double ca) {
    write_profiles(frames);
    if (!renderer) {
      ++frames;
      return;
    }
    render::Snapshot sn = snapshot(m, ca);
    sn.frame = frames++;
    if (!renderer->submit_frame(std::move(sn))) {
      say("renderer stopped: " + renderer->error() + "; frames are no longer written");
      event({{"event", "warning"}, {"cause", "renderer"}, {"message", renderer->error()}});
      renderer->stop();
      renderer.reset();
    }
  }

  // ParaView surface (node grid, tensions) + the .pvd collection entry.
  void write_vtk(const Measures& m, double ca) {
    if (!pvd) pvd = std::make_unique<output::PvdCollection>((dir / figures::kSurfaceCollection).string());
    fs::create_directories(dir / "vtk");
    output::VtkSurface v = figures::vtk_from_snapshot(snapshot(m, ca));
    const std::string name = figures::surface_file_name(vtk_index++);
    output::write_vtp((dir / name).string(), v);
    pvd->add(cap->time(), name);
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
    ++rows;
  }

  void write_steady(const Measures& m, double ca) {
    const auto& d = m.shape;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", ca,
                  d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.area, d.edge_curvature, m.tau_max,
                  m.tau_min);
    steady << buf;
    steady.flush();
    ++steady_rows;
  }

  void write_checkpoint(const std::string& why) {
    output::Checkpoint c;
    const Eigen::Matrix3Xd& x = cap->positions();
    c.put("x", std::vector<double>(x.data(), x.data() + x.size()));
    c.put_scalar("t", cap->time());
    c.put_int("steps", cap->step_count());
    c.put_int("elements", opt.mesh.elements);
    c.put_int("nb", opt.mesh.nb);
    c.put_int("division", static_cast<int>(opt.mesh.division));
    c.put("law", membrane::to_string(opt.law.kind));
    c.put("schedule", schedule->state());
    const Eigen::Matrix3Xd& n = health->normals();
    c.put("health_normals", std::vector<double>(n.data(), n.data() + n.size()));
    c.put("health_flags", health->flags());
    c.put_int("frames", frames);
    c.put_int("vtk_index", vtk_index);
    c.put_int("rows", rows);
    c.put_int("steady_rows", steady_rows);
    c.put_int("resumes", resumes);
    c.put_scalar("wall_s", wall());
    c.put_int("checkpoint_now_seen", checkpoint_now_seen ? 1 : 0);
    c.put("control", control::to_json_text(opt));
    const fs::path cdir = dir / "checkpoints";
    fs::create_directories(cdir);
    char name[64];
    std::snprintf(name, sizeof name, "ckpt_%010ld.ckpt", cap->step_count());
    const fs::path path = cdir / name;
    c.write(path.string());
    // Keep the three newest.
    std::vector<fs::path> all;
    for (const auto& e : fs::directory_iterator(cdir))
      if (e.path().extension() == ".ckpt") all.push_back(e.path());
    std::sort(all.begin(), all.end());
    for (size_t k = 0; k + 3 < all.size(); ++k) fs::remove(all[k]);
    event({{"event", "checkpoint"}, {"file", path.string()}, {"why", why}, {"steps", cap->step_count()}});
    log << "[" << iso_now() << "] checkpoint " << path.string() << " (" << why << ")" << std::endl;
  }

  // Applies a saved edit of the control file (step boundary).
  void check_edits() {
    if (!watcher || !watcher->changed()) return;
    control::ParsedControl edited;
    try {
      edited = control::load_control_file(control_source);
    } catch (const control::ControlError& e) {
      json errs = json::array();
      for (const auto& i : e.issues()) errs.push_back(i.str());
      say("refused edit of " + control_source + " (the run keeps its settings):\n  " +
          std::string(e.what()).substr(std::string(e.what()).find('\n') + 1));
      event({{"event", "edit"}, {"accepted", false}, {"errors", errs}});
      return;
    }
    const control::EditResult r = control::apply_edit(opt, edited.options);
    json applied = json::object(), refused = json::object();
    for (const auto& c : r.applied) applied[c.path] = {{"old", json::parse(c.old_value)}, {"new", json::parse(c.new_value)}};
    for (const auto& c : r.refused)
      refused[c.path] = {{"old", json::parse(c.old_value)}, {"new", json::parse(c.new_value)}, {"reason", c.reason}};
    if (r.applied.empty() && r.refused.empty()) return;  // saved without changes
    const double t = cap->time();
    const double ca_before = schedule->ca(t);
    opt = r.merged;
    cap->set_volume_correction(opt.numerics.volume_correction);
    if (r.schedule_changed) schedule->replace(opt.ca, opt.steady, t);
    if (opt.numerics.threads > 0) omp_set_num_threads(opt.numerics.threads);
    write_effective_control();
    std::ostringstream m;
    m << "edit applied at t = " << t << ":";
    for (const auto& c : r.applied) m << " " << c.path << " " << c.old_value << " -> " << c.new_value << ";";
    for (const auto& c : r.refused) m << " refused " << c.path << " (" << c.reason << ");";
    if (r.schedule_changed) m << " Ca " << ca_before << " -> " << schedule->ca(t);
    say(m.str());
    for (const auto& w : edited.warnings) say("warning: " + w.str());
    event({{"event", "edit"}, {"accepted", true}, {"applied", applied}, {"refused", refused},
           {"ca", schedule->ca(t)}});
  }
};

Simulation::Simulation() : impl_(std::make_unique<Impl>()) {}

Simulation::Simulation(const control::ControlOptions& options, const std::string& control_source)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.opt = options;
  s.dir = options.output.dir;
  s.control_source = control_source;
  if (!options.start.from.empty()) {
    // Refuse before anything in the run directory is created or truncated: starting from a
    // checkpoint inside this run's own directory would overwrite the source's outputs.
    auto inside = [](const fs::path& p, const fs::path& dir) {
      const std::string a = fs::weakly_canonical(fs::absolute(p)).string() + "/";
      const std::string b = fs::weakly_canonical(fs::absolute(dir)).string() + "/";
      return a.compare(0, b.size(), b) == 0;
    };
    if (inside(options.start.from, s.dir))
      throw std::runtime_error("start.from: " + options.start.from + " is in this run's own directory (output.dir " +
                               s.dir.string() + "), whose outputs a new run overwrites: give another "
                               "run's directory, or continue this run with --resume");
  }
  std::error_code ec;
  fs::create_directories(s.dir, ec);
  if (ec)
    throw std::runtime_error("cannot create the run directory " + s.dir.string() + ": " + ec.message());
  s.open_files(false);
  s.write_effective_control();
  {
    std::ofstream src(s.dir / "control.source", std::ios::trunc);
    src << (control_source.empty() ? "" : fs::absolute(control_source).string()) << "\n";
  }
  s.build_solver(options.start.from.empty() ? nullptr : &options.start);
  s.checkpoint_now_seen = options.run.checkpoint_now;
  if (!control_source.empty()) s.watcher = std::make_unique<control::FileWatcher>(control_source);
  s.start_renderer();
}

std::string Simulation::latest_checkpoint(const std::string& run_dir) {
  const fs::path cdir = fs::path(run_dir) / "checkpoints";
  std::string best;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(cdir, ec))
    if (e.path().extension() == ".ckpt" && e.path().string() > best) best = e.path().string();
  return best;
}

std::unique_ptr<Simulation> Simulation::resume(const std::string& run_dir, const ResumeOverrides& ov) {
  const fs::path dir(run_dir);
  if (!fs::is_directory(dir)) throw std::runtime_error(run_dir + ": no such run directory");
  const std::string ckpt = latest_checkpoint(run_dir);
  if (ckpt.empty()) throw std::runtime_error(run_dir + ": no checkpoint in checkpoints/ to resume from");
  const output::Checkpoint c = output::Checkpoint::read(ckpt);
  control::ParsedControl parsed;
  try {
    parsed = control::parse_control(c.text("control"), ckpt + " (stored control)");
  } catch (const control::ControlError& e) {
    throw std::runtime_error(e.what());
  }
  std::unique_ptr<Simulation> sim(new Simulation());
  Impl& s = *sim->impl_;
  s.opt = parsed.options;
  if (ov.t_end) s.opt.time.t_end = *ov.t_end;
  s.opt.output.dir = dir.string();
  s.dir = dir;
  s.opt.run.state = control::RunState::Running;
  if (c.integer("elements") != s.opt.mesh.elements || c.integer("nb") != s.opt.mesh.nb ||
      checkpoint_division(c, ckpt) != s.opt.mesh.division)
    throw std::runtime_error(ckpt + ": checkpoint mesh does not match its control");
  s.build_solver();
  const long n = s.mesh->num_local();
  const auto& x = c.doubles("x", 3 * n);
  s.cap->set_state(Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, n), c.scalar("t"), c.integer("steps"));
  s.schedule->restore(c.doubles("schedule"));
  const auto& nrm = c.doubles("health_normals", 3 * n);
  s.health->restore(Eigen::Map<const Eigen::Matrix3Xd>(nrm.data(), 3, n), c.doubles("health_flags"));
  s.frames = c.integer("frames");
  s.vtk_index = c.integer("vtk_index");
  if (fs::exists(dir / figures::kSurfaceCollection)) {
    s.pvd = std::make_unique<output::PvdCollection>((dir / figures::kSurfaceCollection).string());
    s.pvd->truncate_after(c.scalar("t"));
  }
  s.rows = c.integer("rows");
  s.steady_rows = c.integer("steady_rows");
  s.resumes = c.integer("resumes") + 1;
  s.wall_offset = c.scalar("wall_s");
  s.checkpoint_now_seen = c.integer("checkpoint_now_seen") != 0;
  truncate_csv(dir / "timeseries.csv", s.rows);
  truncate_csv(dir / "steady.csv", s.steady_rows);
  s.open_files(true);
  s.write_effective_control();
  {
    std::ifstream src(dir / "control.source");
    std::string line;
    if (src && std::getline(src, line) && !line.empty() && fs::exists(line)) {
      s.control_source = line;
      s.watcher = std::make_unique<control::FileWatcher>(line);
    }
  }
  s.event({{"event", "resume"}, {"checkpoint", ckpt}, {"steps", s.cap->step_count()}});
  s.say("resuming " + dir.string() + " from " + ckpt + " at t = " + std::to_string(s.cap->time()));
  s.start_renderer();
  return sim;
}

Simulation::~Simulation() {
  if (impl_ && impl_->renderer) impl_->renderer->stop();
}

RunSummary Simulation::run(const std::atomic<bool>* stop) {
  Impl& s = *impl_;
  s.start = std::chrono::steady_clock::now();
  RunSummary sum;
  const bool fresh = s.cap->step_count() == 0 && s.rows == 0;
  {
    const control::ControlOptions& o = s.opt;
    std::ostringstream m;
    m << "capflow run: " << membrane::to_string(o.law.kind) << ", " << o.flow.name() << ", NE="
      << o.mesh.elements << (o.mesh.division == geometry::Division::Cube
                                  ? ""
                                  : std::string(" (") + control::division_name(o.mesh.division) +
                                        " division)")
      << " NB=" << o.mesh.nb << ", dt=" << o.time.dt << ", t_end=" << o.time.t_end
      << ", " << omp_get_max_threads() << " threads, symmetry targets "
      << s.cap->symmetry().targets().size() << "/" << s.mesh->num_unique();
    if (o.numerics.quadrature_scale != 1.0)
      m << ", quadrature orders x" << o.numerics.quadrature_scale;
    m << " -> " << s.dir.string();
    if (s.watcher)
      m << "; watching " << s.control_source << (s.watcher->using_inotify() ? " (inotify)" : " (polling)");
    s.say(m.str());
    if (fresh) s.event({{"event", "start"}, {"control", json::parse(control::to_json_text(o))}});
  }
  Measures m = s.measure(true);
  if (fresh) {
    const double ca0 = s.schedule->ca(s.cap->time());  // t > 0 after start.from
    s.write_row(m, ca0);
    if (s.opt.output.frame_every > 0) s.submit_frame(m, ca0);
    if (s.opt.output.vtk_every > 0) s.write_vtk(m, ca0);
  }
  double t = s.cap->time();
  double next_csv = next_after(t, s.opt.output.csv_every);
  double next_frame = next_after(t, s.opt.output.frame_every);
  double next_ckpt = next_after(t, s.opt.output.checkpoint_every);
  double next_vtk = next_after(t, s.opt.output.vtk_every);
  double next_sample = t;
  double last_status = -1;
  const long steps_at_start = s.cap->step_count();
  bool paused_logged = false;
  std::string reason = "t_end reached";
  for (;;) {
    const control::OutputOptions before = s.opt.output;
    s.check_edits();
    const control::ControlOptions& o = s.opt;
    if (o.output.csv_every != before.csv_every) next_csv = next_after(t, o.output.csv_every);
    if (o.output.frame_every != before.frame_every) next_frame = next_after(t, o.output.frame_every);
    if (o.output.checkpoint_every != before.checkpoint_every) next_ckpt = next_after(t, o.output.checkpoint_every);
    if (o.output.vtk_every != before.vtk_every) next_vtk = next_after(t, o.output.vtk_every);
    if (o.run.checkpoint_now && !s.checkpoint_now_seen) s.write_checkpoint("run.checkpoint_now");
    s.checkpoint_now_seen = o.run.checkpoint_now;
    if (stop && stop->load()) {
      reason = "stopped by signal";
      break;
    }
    if (o.run.state == control::RunState::Stopped) {
      reason = "run.state is \"stopped\"";
      break;
    }
    if (o.run.state == control::RunState::Paused) {
      if (!paused_logged) {
        s.say("paused at t = " + std::to_string(t) + " (set run.state to \"running\" to continue)");
        s.event({{"event", "pause"}});
        paused_logged = true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    if (paused_logged) {
      s.say("running again");
      s.event({{"event", "continue"}});
      paused_logged = false;
    }
    const double dt = o.time.dt;
    if (t >= o.time.t_end - 0.5 * dt) break;

    bool stop_at_steady = false;
    const Eigen::Matrix3Xd last_good = s.cap->positions();
    const long steps_prev = s.cap->step_count();
    std::string failure;
    try {
      s.cap->step(dt, [&](double tt) { return s.schedule->ca(tt); });
    } catch (const std::exception& e) {
      failure = "the step from t = " + std::to_string(t) + " failed: " + e.what();
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
      s.cap->set_state(last_good, t, steps_prev);
      sum.failed = true;
      sum.failure = failure;
      s.say("failure: " + failure + " (keeping the last good state, t = " + std::to_string(t) + ")");
      s.event({{"event", "failure"}, {"message", failure}});
      reason = "failure";
      break;
    }
    t = s.cap->time();
    const double eps = 1e-9 * dt;
    const bool frame = t >= next_frame - eps;
    const bool vtk = t >= next_vtk - eps;
    const bool csv = t >= next_csv - eps || frame || vtk;
    const bool sample = t >= next_sample - eps;
    if (csv || sample) {
      m = s.measure(csv);
      if (sample) {
        // Shape samples for steady-state detection: about 20 per window.
        next_sample = t + std::min(o.steady.window / 20.0, o.output.csv_every) - eps;
        const control::CaScheduler::Event ev = s.schedule->sample(t, m.shape.L, m.shape.S, m.shape.W);
        if (ev.steady) {
          if (!csv) m = s.measure(true);
          s.write_steady(m, s.schedule->level());
          ++sum.steady_states;
          if (o.steady.stop && s.schedule->in_final_hold()) stop_at_steady = true;
        }
        if (ev.steady || ev.level_changed) {
          s.say(ev.description);
          s.event({{"event", ev.steady ? "steady" : "level"}, {"message", ev.description},
                   {"ca", s.schedule->ca(t)}, {"D", m.shape.D}, {"L", m.shape.L}});
        }
      }
      if (frame) {
        s.submit_frame(m, s.schedule->ca(t));
        next_frame = next_after(t, o.output.frame_every);
      }
      if (vtk) {
        s.write_vtk(m, s.schedule->ca(t));
        next_vtk = next_after(t, o.output.vtk_every);
      }
      if (csv) {
        if (t >= next_csv - eps) {
          s.write_row(m, s.schedule->ca(t));
          next_csv = next_after(t, o.output.csv_every);
        }
        if (s.renderer && o.render.preview) s.renderer->offer_preview(s.snapshot(m, s.schedule->ca(t)));
        const capsule::HealthReport w =
            s.health->check_wrinkling(t, m.tau_min, m.tau_min_at, s.schedule->max_rate());
        if (w.level == capsule::HealthLevel::Warning) {
          s.say("warning: " + w.message);
          s.event({{"event", "warning"}, {"cause", w.cause}, {"message", w.message}});
        }
      }
    }
    if (t >= next_ckpt - eps) {
      s.write_checkpoint("output.checkpoint_every");
      next_ckpt = next_after(t, o.output.checkpoint_every);
    }
    // Progress: at most once per second on a terminal, every 10 s otherwise.
    const double wall = s.wall();
    if (wall - last_status >= (s.tty ? 1.0 : 10.0)) {
      last_status = wall;
      const double session =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - s.start).count();
      const double rate = (s.cap->step_count() - steps_at_start) / std::max(session, 1e-9);
      const double eta = (o.time.t_end - t) / dt / std::max(rate, 1e-9);
      const double eta_steady = s.schedule->eta_steady(t);
      std::ostringstream line;
      line << std::fixed << std::setprecision(4) << "t=" << t << " Ca=" << s.schedule->ca(t)
           << " D=" << m.shape.D << " " << std::setprecision(1) << rate << " steps/s, ETA "
           << std::setprecision(0) << eta << " s to t_end";
      if (eta_steady >= 0) line << std::setprecision(2) << ", steady in ~" << eta_steady << " (sim. time)";
      if (s.tty)
        std::cerr << "\r\033[K" << line.str() << std::flush;
      else
        s.say(line.str());
    }
    if (stop_at_steady) {
      reason = "steady state of the final level (steady.stop)";
      break;
    }
  }
  m = s.measure(true);
  try {
    s.write_checkpoint(reason);
  } catch (const std::exception& e) {
    s.say(std::string("warning: final checkpoint failed: ") + e.what());
  }
  if (s.renderer) {
    const render::RenderStats rs = s.renderer->stop();
    std::ostringstream r;
    r << "renderer: " << rs.movie_frames << " movie frames written, solver waited "
      << rs.producer_waits << " times for the renderer";
    if (!s.renderer->error().empty()) r << "; error: " << s.renderer->error();
    s.say(r.str());
    s.renderer.reset();
  }
  sum.reason = reason;
  sum.t = s.cap->time();
  sum.steps = s.cap->step_count();
  sum.wall_s = s.wall();
  sum.D = m.shape.D;
  sum.L = m.shape.L;
  sum.S = m.shape.S;
  sum.W = m.shape.W;
  sum.volume_drift = m.shape.volume / s.cap->initial_volume() - 1.0;
  std::ostringstream fin;
  fin << "end (" << reason << "): t=" << sum.t << " steps=" << sum.steps << " wall=" << std::fixed
      << std::setprecision(1) << sum.wall_s << " s, D=" << std::setprecision(5) << sum.D
      << " L=" << sum.L << " S=" << sum.S << " W=" << sum.W << ", volume drift "
      << std::scientific << std::setprecision(2) << sum.volume_drift << ", steady states "
      << s.steady_rows;
  s.say(fin.str());
  s.event({{"event", "end"}, {"reason", reason}, {"steps", sum.steps}, {"D", sum.D}, {"L", sum.L},
           {"S", sum.S}, {"W", sum.W}, {"volume_drift", sum.volume_drift}, {"wall_s", sum.wall_s}});
  return sum;
}

}  // namespace capflow::app
