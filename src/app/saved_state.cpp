#include "app/saved_state.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "app/errors.h"
#include "app/frames.h"
#include "app/run_checkpoint.h"
#include "app/surface_files.h"
#include "capsule/capsule.h"
#include "control/control_file.h"
#include "control/options.h"
#include "diagnostics/diagnostics.h"
#include "membrane/law.h"
#include "output/vtk.h"

namespace capflow::app {

namespace fs = std::filesystem;

namespace {

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The checkpoint's state as the renderer's data: tensions from its law, the shape diagnostics.
SavedState from_checkpoint(const RunCheckpoint& ck) {
  const control::ControlOptions& o = ck.options;
  const capsule::Capsule cap(*ck.mesh, o.law, o.flow, control::dynamics_options(o));
  diagnostics::ShapeOptions so;
  so.axes = o.flow.type == capsule::FlowType::SimpleShear ? diagnostics::AxesMode::Shear
                                                          : diagnostics::AxesMode::FlowAxes;
  so.extrema = false;  // the overlay shows D, L, S and W only
  so.edge_curvature = false;
  const diagnostics::ShapeDiagnostics d = diagnostics::measure_shape(*ck.mesh, ck.x, so);
  SavedState s;
  s.snapshot =
      state_snapshot(cap, ck.x, ck.t, ck.ca, membrane::to_string(o.law.kind), {d.D, d.L, d.S, d.W});
  const auto& t1 = s.snapshot.tau1;  // the tensions state_snapshot computed
  const auto& t2 = s.snapshot.tau2;
  s.snapshot.diag.tau_max = *std::max_element(t1.begin(), t1.end());
  s.snapshot.diag.tau_min = *std::min_element(t2.begin(), t2.end());
  s.camera = o.render.camera;
  s.note = "checkpoint " + ck.path + " (t = " + num(ck.t) + ")";
  return s;
}

SavedState from_vtp(const std::string& path) {
  output::VtkSurface v;
  try {
    v = output::read_vtp(path);
  } catch (const std::exception& e) {
    throw UserError(e.what());
  }
  SavedState s;
  s.snapshot = snapshot_from_vtk(v);
  std::string err;
  if (!s.snapshot.IsValid(&err)) throw UserError(path + ": " + err);
  s.note = "surface " + path + " (t = " + num(v.time) + ")";
  return s;
}

}  // namespace

SavedState load_saved_state(const std::string& source, std::optional<double> time) {
  const fs::path p(source);
  if (!fs::exists(p)) throw UserError(source + ": no such file or directory");
  if (fs::is_regular_file(p) && p.extension() == ".vtp") return from_vtp(source);
  if (fs::is_regular_file(p)) return from_checkpoint(read_run_checkpoint(source));
  if (!fs::is_directory(p))
    throw UserError(source + ": neither a run directory, a .ckpt nor a .vtp file");
  std::optional<RunCheckpoint> latest;
  std::string why_not;
  try {
    latest = read_latest_checkpoint(p);
  } catch (const UserError& e) {
    why_not = e.what();
  }
  if (time) {
    render::Snapshot sn;
    std::string note;
    if (load_surface(source, *time, &sn, &note)) {
      SavedState s;
      s.snapshot = std::move(sn);
      if (latest) s.camera = latest->options.render.camera;
      s.note = note + " (t = " + num(s.snapshot.time) + ", nearest to " + num(*time) + ")";
      return s;
    }
    if (!latest) throw UserError(note + "; and " + why_not);
    SavedState s = from_checkpoint(*latest);
    s.note += " (" + note + ": the newest checkpoint instead of t = " + num(*time) + ")";
    return s;
  }
  if (!latest) throw UserError(why_not);
  return from_checkpoint(*latest);
}

}  // namespace capflow::app
