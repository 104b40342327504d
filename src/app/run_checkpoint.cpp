#include "app/run_checkpoint.h"

#include <cmath>

#include "app/errors.h"
#include "app/run_directory.h"
#include "control/control_file.h"
#include "control/schedule.h"
#include "geometry/surface.h"
#include "output/checkpoint.h"

namespace capflow::app {

namespace fs = std::filesystem;

namespace {

// Node positions beyond this many capsule radii are not a capsule's.
constexpr double kMaxCoordinate = 1e4;

std::vector<double> flat(const Eigen::Matrix3Xd& m) {
  return {m.data(), m.data() + m.size()};
}

geometry::Division division_of(const output::Checkpoint& c) {
  if (!c.has("division")) return geometry::Division::Cube;
  const int64_t d = c.integer("division");
  if (d < 0 || d > 2)
    throw output::CheckpointError(c.source + ": invalid element division " + std::to_string(d) +
                                  " in the checkpoint (0 cube, 1 box, 2 diagonal)");
  return static_cast<geometry::Division>(d);
}

RunCheckpoint decode(const output::Checkpoint& c) {
  const std::string& p = c.source;
  RunCheckpoint s;
  s.path = p;
  s.control = c.text("control");
  s.control_file = c.has("control_file") ? c.text("control_file") : s.control;
  try {
    s.options = control::parse_control(s.control, p + " (stored control)").options;
    s.file_options = c.has("control_file")
                         ? control::parse_control(s.control_file, p + " (stored control file)")
                               .options
                         : s.options;
  } catch (const control::ControlError& e) {
    throw output::CheckpointError(e.what());
  }
  const control::MeshOptions m{static_cast<int>(c.integer("elements")),
                               static_cast<int>(c.integer("nb")), division_of(c)};
  if (m.elements != s.options.mesh.elements || m.nb != s.options.mesh.nb ||
      m.division != s.options.mesh.division)
    throw output::CheckpointError(p + ": the checkpoint's mesh does not match its stored control");
  try {
    s.mesh = control::make_mesh(m);
  } catch (const std::invalid_argument& e) {
    throw output::CheckpointError(p + ": invalid mesh in the checkpoint (" + e.what() + ")");
  }
  const long n = s.mesh->num_local();
  const auto& x = c.doubles("x", 3 * n);
  s.x = Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, n);
  if (!s.x.allFinite()) throw output::CheckpointError(p + ": the stored shape is not finite");
  if (s.x.cwiseAbs().maxCoeff() > kMaxCoordinate)
    throw output::CheckpointError(p + ": the stored shape reaches " +
                                  std::to_string(s.x.cwiseAbs().maxCoeff()) +
                                  " capsule radii from the origin (at most " +
                                  std::to_string(kMaxCoordinate) + ")");
  const Eigen::VectorXd jac = geometry::compute_geometry(*s.mesh, s.x).jac;
  if (!jac.allFinite() || !(jac.minCoeff() > 0))
    throw output::CheckpointError(
        p + ": the stored shape is not a surface (an element of zero or non-finite area)");
  s.t = c.scalar("t");
  if (!std::isfinite(s.t) || s.t < 0)
    throw output::CheckpointError(p + ": invalid time t in the checkpoint");
  s.steps = c.integer("steps");
  s.schedule = c.doubles("schedule");
  try {
    control::CaScheduler sched(s.options.ca, s.options.steady, 0.0, 0.0);
    sched.restore(s.schedule);
    s.ca = c.has("ca") ? c.scalar("ca") : sched.ca(s.t);
  } catch (const std::invalid_argument& e) {
    throw output::CheckpointError(p + ": " + e.what());
  }
  if (!(std::isfinite(s.ca) && s.ca > 0))
    throw output::CheckpointError(p + ": invalid Ca in the checkpoint");
  const auto& nrm = c.doubles("health_normals", 3 * n);
  s.health_normals = Eigen::Map<const Eigen::Matrix3Xd>(nrm.data(), 3, n);
  s.health_flags = c.doubles("health_flags");
  s.frames = c.integer("frames");
  s.vtk_index = c.integer("vtk_index");
  s.rows = c.integer("rows");
  s.steady_rows = c.integer("steady_rows");
  s.resumes = c.integer("resumes");
  s.wall_s = c.scalar("wall_s");
  s.checkpoint_now_seen = c.integer("checkpoint_now_seen") != 0;
  if (c.has("pending_outputs")) {
    const int64_t bits = c.integer("pending_outputs");
    s.pending_row = bits & 1;
    s.pending_frame = bits & 2;
    s.pending_vtk = bits & 4;
  }
  if (c.has("pending_steady_ca")) s.pending_steady_ca = c.scalar("pending_steady_ca");
  if (c.has("pending_ca")) s.pending_ca = c.scalar("pending_ca");
  if (c.has("h_next")) s.h_next = c.scalar("h_next");
  if (!(std::isfinite(s.h_next) && s.h_next >= 0 && s.h_next <= 1))
    throw output::CheckpointError(p + ": invalid h_next (the adaptive step) in the checkpoint");
  if (c.has("step_history")) {
    // e_prev, steps, h_free and (time.method "chebyshev") the spectral radius rho.
    const auto& h = c.doubles("step_history");
    const double rho = h.size() == 4 ? h[3] : 0.0;
    capsule::Integrator::History hist;
    if (h.size() == 3 || h.size() == 4) {
      hist.e_prev = h[0];
      hist.steps = static_cast<long>(h[1]);
      hist.h_free = h[2];
      hist.rho = rho;
    }
    if (!(h.size() == 3 || h.size() == 4) ||
        !(std::isfinite(h[0]) && h[0] >= 0 && h[1] >= 0 && h[1] <= 1e15 && h[1] == std::floor(h[1]) &&
          std::isfinite(h[2]) && h[2] >= 0 && h[2] <= 1 && std::isfinite(rho) && rho >= 0))
      throw output::CheckpointError(p + ": invalid step_history (the adaptive controller's state)");
    s.step_history = hist;
  }
  if (c.has("krylov_warm")) {
    const auto& w = c.doubles("krylov_warm");
    s.krylov_warm =
        Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
    if (!s.krylov_warm.allFinite() || s.krylov_warm.size() % 3 != 0 ||
        s.options.viscosity_ratio == 1.0)
      throw output::CheckpointError(p +
                                    ": invalid krylov_warm (the viscosity-ratio solve's start)");
  }
  if (c.has("note"))
    s.note = c.text("note");
  else if (c.has("extrapolated"))
    s.note = c.text("extrapolated");
  if (s.steps < 0 || s.frames < 0 || s.vtk_index < 0 || s.rows < 0 || s.steady_rows < 0 ||
      s.resumes < 0)
    throw output::CheckpointError(p + ": negative counters in the checkpoint");
  return s;
}

}  // namespace

void write_run_checkpoint(const RunCheckpoint& s, const std::string& path) {
  output::Checkpoint c;
  c.put("x", flat(s.x));
  c.put_scalar("t", s.t);
  c.put_int("steps", s.steps);
  c.put_int("elements", s.options.mesh.elements);
  c.put_int("nb", s.options.mesh.nb);
  c.put_int("division", static_cast<int>(s.options.mesh.division));
  c.put("law", membrane::to_string(s.options.law.kind));
  c.put_scalar("ca", s.ca);
  c.put("schedule", s.schedule);
  c.put("health_normals", flat(s.health_normals));
  c.put("health_flags", s.health_flags);
  c.put_int("frames", s.frames);
  c.put_int("vtk_index", s.vtk_index);
  c.put_int("rows", s.rows);
  c.put_int("steady_rows", s.steady_rows);
  c.put_int("resumes", s.resumes);
  c.put_scalar("wall_s", s.wall_s);
  c.put_int("checkpoint_now_seen", s.checkpoint_now_seen ? 1 : 0);
  c.put("control", s.control);
  c.put("control_file", s.control_file);
  c.put_int("pending_outputs",
            (s.pending_row ? 1 : 0) | (s.pending_frame ? 2 : 0) | (s.pending_vtk ? 4 : 0));
  c.put_scalar("pending_steady_ca", s.pending_steady_ca);
  c.put_scalar("pending_ca", s.pending_ca);
  c.put_scalar("h_next", s.h_next);
  if (s.step_history) {
    std::vector<double> h{s.step_history->e_prev, static_cast<double>(s.step_history->steps),
                          s.step_history->h_free};
    if (s.step_history->rho > 0) h.push_back(s.step_history->rho);
    c.put("step_history", h);
  }
  if (s.krylov_warm.size() > 0)
    c.put("krylov_warm",
          std::vector<double>(s.krylov_warm.data(), s.krylov_warm.data() + s.krylov_warm.size()));
  if (!s.note.empty()) c.put("note", s.note);
  try {
    c.write(path);
  } catch (const output::CheckpointError& e) {
    throw OutputError(e.what());
  }
}

RunCheckpoint read_run_checkpoint(const std::string& path) {
  try {
    return decode(output::Checkpoint::read(path));
  } catch (const output::CheckpointError& e) {
    throw UserError(e.what());
  }
}

RunCheckpoint read_latest_checkpoint(const fs::path& where, std::vector<std::string>* skipped,
                                     const CheckpointFits& fits) {
  std::error_code ec;
  if (!fs::is_directory(where, ec)) {
    if (!fs::is_regular_file(where, ec))
      throw UserError(where.string() + ": no such run directory or checkpoint file");
    return read_run_checkpoint(where.string());
  }
  const std::vector<fs::path> all = RunDirectory::checkpoints(where);
  if (all.empty()) throw UserError(where.string() + ": no checkpoint in checkpoints/");
  std::string why;
  for (const fs::path& p : all) {
    std::string not_this;
    try {
      RunCheckpoint c = read_run_checkpoint(p.string());
      if (fits) not_this = fits(c);
      if (not_this.empty()) return c;
      not_this = p.string() + ": " + not_this;
    } catch (const UserError& e) {
      not_this = e.what();
    }
    why += "\n  " + not_this;
    if (skipped) skipped->push_back(not_this);
  }
  throw UserError(where.string() + ": none of its " + std::to_string(all.size()) +
                  " checkpoints can be read:" + why);
}

}  // namespace capflow::app
