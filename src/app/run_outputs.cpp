// capflow/app/run_outputs: see run_outputs.h.
#include "app/run_outputs.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "app/errors.h"
#include "app/frames.h"
#include "app/surface_export.h"
#include "app/surface_files.h"
#include "membrane/membrane.h"
#include "output/records.h"

namespace capflow::app {

const char* phase_name(RunPhase p) {
  switch (p) {
    case RunPhase::Running:
      return "running";
    case RunPhase::Paused:
      return "paused";
    case RunPhase::Stopped:
      return "stopped";
    case RunPhase::Finished:
      return "finished";
  }
  return "";
}

namespace {

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

}  // namespace

Measures measure_state(const capsule::Capsule& cap, bool full) {
  Measures m;
  diagnostics::ShapeOptions so;
  so.axes = cap.flow().type == capsule::FlowType::SimpleShear ? diagnostics::AxesMode::Shear
                                                              : diagnostics::AxesMode::FlowAxes;
  so.extrema = full;
  so.edge_curvature = full;
  m.shape = diagnostics::measure_shape(cap.mesh(), cap.positions(), so);
  if (full) {
    const membrane::MembraneFields f = cap.fields(cap.positions());
    Eigen::Index imax, imin;
    m.tau_max = f.tension1.maxCoeff(&imax);
    m.tau_min = f.tension2.minCoeff(&imin);
    m.tau_min_at = cap.positions().col(imin);
    if (cap.bending()) m.bending_energy = cap.bending()->energy(cap.positions());
  }
  return m;
}

RunOutputs::RunOutputs(RunLifecycle& life, const control::ControlOptions& options)
    : life_(life), opt_(options), pending_steady_ca_(std::numeric_limits<double>::quiet_NaN()) {}

RunOutputs::~RunOutputs() = default;

void RunOutputs::store(RunCheckpoint* c) const {
  c->frames = frames_on_disk();
  c->vtk_index = vtk_index_;
  c->rows = rows_;
  c->steady_rows = steady_rows_;
  c->pending_row = pending_.row;
  c->pending_frame = pending_.frame;
  c->pending_vtk = pending_.vtk;
  c->pending_steady_ca = pending_steady_ca_;
  c->pending_ca = pending_ca_;
}

void RunOutputs::restore(const RunCheckpoint& c) {
  frames_ = session_first_frame_ = c.frames;
  vtk_index_ = c.vtk_index;
  rows_ = c.rows;
  steady_rows_ = c.steady_rows;
  pending_.row = c.pending_row;
  pending_.frame = c.pending_frame;
  pending_.vtk = c.pending_vtk;
  pending_steady_ca_ = c.pending_steady_ca;
  pending_ca_ = c.pending_ca;
  RunDirectory& dir = life_.dir();
  std::error_code ec;
  if (std::filesystem::exists(dir.file(kSurfaceCollection), ec))
    as_output("cannot rewrite " + dir.file(kSurfaceCollection).string(), [&] {
      pvd_ = std::make_unique<output::PvdCollection>(dir.file(kSurfaceCollection).string());
      pvd_->truncate_after(c.t);
    });
}

void RunOutputs::begin(const Due& due, double ca, std::optional<double> steady_ca) {
  pending_ = due;
  pending_.checkpoint = false;
  pending_ca_ = ca;
  pending_steady_ca_ = steady_ca ? *steady_ca : std::numeric_limits<double>::quiet_NaN();
}

bool RunOutputs::pending() const {
  return pending_.full_measure() || !std::isnan(pending_steady_ca_);
}

void RunOutputs::write_steady(const StateRecord& s) {
  if (std::isnan(pending_steady_ca_)) return;
  const auto& d = s.m.shape;
  life_.dir().steady().append(output::records::format_row(
      output::records::steady_run(),
      {s.cap->time(), pending_steady_ca_, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.area,
       d.edge_curvature, s.m.tau_max, s.m.tau_min}));
  ++steady_rows_;
  pending_steady_ca_ = std::numeric_limits<double>::quiet_NaN();
}

void RunOutputs::write_due(const StateRecord& state) {
  StateRecord s = state;
  s.ca = pending_ca_;
  if (pending_.frame) {
    write_frame(s);
    pending_.frame = false;
  }
  if (pending_.vtk) {
    write_surface(s);
    pending_.vtk = false;
  }
  if (pending_.row) {
    write_row(s);
    pending_.row = false;
  }
  notify(s);
}

void RunOutputs::offer_preview(const StateRecord& s) {
  if (render::RenderThread* r = life_.renderer(); r && opt_.render.preview)
    r->offer_preview(snapshot(s));
}

render::Snapshot RunOutputs::snapshot(const StateRecord& s) const {
  const Measures& m = s.m;
  return state_snapshot(*s.cap, s.cap->positions(), s.cap->time(), s.ca,
                        membrane::to_string(opt_.law.kind),
                        {m.shape.D, m.shape.L, m.shape.S, m.shape.W, m.tau_max, m.tau_min});
}

void RunOutputs::write_row(const StateRecord& s) {
  const auto& d = s.m.shape;
  const capsule::Capsule& cap = *s.cap;
  life_.dir().timeseries().append(output::records::format_row(
      output::records::timeseries(),
      {cap.time(), s.ca, d.D, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.area, d.volume,
       d.edge_curvature, s.m.tau_max, s.m.tau_min, s.m.bending_energy, d.inclination_deg,
       d.volume / cap.initial_volume() - 1.0, static_cast<double>(cap.step_count()), s.dt,
       s.wall}));
  ++rows_;
}

void RunOutputs::write_profiles(const StateRecord& s, long index) {
  const capsule::Capsule& cap = *s.cap;
  std::ostringstream f;
  f << "plane,t,a,b\n";
  const diagnostics::ShapeDiagnostics d = measure_state(cap, false).shape;
  const Eigen::Vector3d c = d.centroid;
  for (const auto& [plane, axis] : {std::pair<const char*, int>{"z", 2}, {"y", 1}}) {
    const Eigen::Vector2d center(c.x(), axis == 2 ? c.y() : c.z());
    for (const Eigen::Vector2d& p :
         diagnostics::cross_section(cap.mesh(), cap.positions(), axis, c[axis], center)) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "%s,%.10g,%.10g,%.10g\n", plane, cap.time(), p.x(), p.y());
      f << buf;
    }
  }
  life_.dir().subdirectory("profiles");
  char name[64];
  std::snprintf(name, sizeof name, "profiles/profile_%06ld.csv", index);
  life_.dir().write_text(name, f.str());
}

void RunOutputs::write_frame(const StateRecord& s) {
  write_profiles(s, frames_);
  render::RenderThread* renderer = life_.renderer();
  if (!renderer) {
    ++frames_;
    return;
  }
  render::Snapshot sn = snapshot(s);
  sn.frame = frames_;
  if (!renderer->submit_frame(std::move(sn)))
    throw OutputError("frames could not be written: " + renderer->error());
  ++frames_;  // handed to the renderer
}

void RunOutputs::write_surface(const StateRecord& s) {
  RunDirectory& dir = life_.dir();
  dir.subdirectory("vtk");
  const std::string name = surface_file_name(vtk_index_);
  as_output("cannot write " + dir.file(name).string(), [&] {
    if (!pvd_)
      pvd_ = std::make_unique<output::PvdCollection>(dir.file(kSurfaceCollection).string());
    output::write_vtp(dir.file(name).string(), surface(s));
    pvd_->add(s.cap->time(), name);
  });
  ++vtk_index_;
}

output::VtkSurface RunOutputs::surface(const StateRecord& s) const {
  capsule::Capsule& cap = *s.cap;
  // one more velocity evaluation; the Krylov warm start (lambda != 1) is put back, so the run
  // goes on as it would without ParaView output
  const Eigen::VectorXd warm = cap.krylov_warm_start();
  const Eigen::Matrix3Xd u = cap.velocity(cap.positions(), s.ca);
  cap.set_krylov_warm_start(warm);
  const render::Snapshot sn = snapshot(s);
  const Eigen::Matrix3Xd& x = cap.positions();
  const int n = opt_.output.vtk_points > 0 ? opt_.output.vtk_points : cap.mesh().nb();
  // the bending energy density the snapshot already holds (render::Snapshot::bending)
  const Eigen::VectorXd bending = Eigen::Map<const Eigen::VectorXd>(
      sn.bending.data(), static_cast<Eigen::Index>(sn.bending.size()));
  return surface_export(cap.mesh(), {&x, &u, &sn, sn.bending.empty() ? nullptr : &bending}, n);
}

long RunOutputs::frames_on_disk() const {
  const render::RenderThread* r = life_.renderer();
  if (!r) return frames_;
  const long through = r->frames_written_through();
  return through >= 0 ? through : session_first_frame_;
}

long RunOutputs::frames_lost_in_flight() const {
  render::RenderThread* r = life_.renderer();
  if (!r) return 0;
  r->wait_idle();
  return std::max(0L, frames_ - frames_on_disk());
}

}  // namespace capflow::app
