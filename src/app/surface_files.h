// capflow/app/surface_files: the run directory's surface files (surface.pvd + vtk/*.vtp), written
// at the run's frame times and read back by `capflow render` and the figures' 3-D views.
//
// Surface files (written with output::write_vtp: n = output.vtk_points Gauss-Lobatto points per
// element edge, app/surface_export.h; NB in runs before it):
//   FieldData: TimeValue, ne, n, and optionally ca, D, L, S, W, tau_max, tau_min
//   PointData: tau1, tau2 (principal tensions), optionally Normals, mean_curvature, velocity
// vtk_from_snapshot() builds exactly that from a render::Snapshot (what the run loop already
// has at each frame), snapshot_from_vtk() is its inverse, and load_surface() finds the saved
// surface nearest in time.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "output/vtk.h"
#include "render/snapshot.h"

namespace capflow::app {

// Run-directory names of the surface export (the run loop writes these; load_surface reads).
inline const char* kSurfaceCollection = "surface.pvd";
std::string surface_file_name(long index);  // vtk/surface_NNNNNN.vtp, relative to the run directory

// The scalars a surface file carries in its FieldData: Ca and the snapshot's diagnostics.
std::map<std::string, double> snapshot_field_scalars(const render::Snapshot& s);

output::VtkSurface vtk_from_snapshot(const render::Snapshot& s);
render::Snapshot snapshot_from_vtk(const output::VtkSurface& v);

// (time, path) of every saved surface of a run: the entries of <run>/surface.pvd when it
// exists (files that are missing are left out), else every vtk/*.vtp (time = its TimeValue).
std::vector<std::pair<double, std::string>> list_surfaces(const std::string& run_dir);

// The saved surface of `run_dir` nearest in time to t, as a render::Snapshot (positions,
// tensions, t, Ca and the diagnostics stored with it; out->time is the time found). Returns
// false when the run has no readable surface file; *note (optional) says which file was used
// or why none was.
bool load_surface(const std::string& run_dir, double t, render::Snapshot* out,
                  std::string* note = nullptr);

}  // namespace capflow::app
