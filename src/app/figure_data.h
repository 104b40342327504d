// capflow/app/figure_data: reading a run directory back for `capflow figure` (header-only, so
// the command and its tests share it without a new library target).
//
// What is read (all written by the run driver, see app/simulation.h):
//   timeseries.csv, steady.csv         numeric CSV with a header row (read_csv)
//   profiles/profile_NNNNNN.csv        plane,t,a,b: plane "z" -> (a,b) = (x,y), "y" -> (x,z)
//   surface.pvd + vtk/surface_NNNNNN.vtp   the surface (output/vtk.h) every output.vtk_every
//   frames/frame_NNNNNN.png            rendered frames; frame NNNNNN shares its index with
//                                      profile NNNNNN (both written at the same frame time)
//
// Surface files (written with output::write_vtp: n = output.vtk_points Gauss-Lobatto points per
// element edge, app/surface_export.h; NB in runs before it):
//   FieldData: TimeValue, ne, n, and optionally ca, D, L, S, W, tau_max, tau_min
//   PointData: tau1, tau2 (principal tensions), optionally Normals, mean_curvature, velocity
// vtk_from_snapshot() builds exactly that from a render::Snapshot (what the run loop already
// has at each frame), snapshot_from_vtk() is its inverse, and load_surface() finds the saved
// surface nearest in time.
//
// Failure: read_csv/read_profile throw std::runtime_error naming the file; load_surface
// returns false (with *note saying why) when the run has no surface data.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "output/vtk.h"
#include "render/snapshot.h"

namespace capflow::app::figures {

namespace fs = std::filesystem;

// Run-directory names of the surface export (the run loop writes these; load_surface reads).
inline const char* kSurfaceCollection = "surface.pvd";
inline std::string surface_file_name(long index) {  // relative to the run directory
  char buf[64];
  std::snprintf(buf, sizeof buf, "vtk/surface_%06ld.vtp", index);
  return buf;
}

// ---------------------------------------------------------------- CSV

struct Table {
  std::string source;                           // the file read
  std::vector<std::string> header;              // column names
  std::vector<std::vector<std::string>> cells;  // rows of text cells

  long rows() const { return static_cast<long>(cells.size()); }
  int col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  }
  // Numeric value of a cell; NaN for an empty or non-numeric cell.
  double num(long row, int col) const {
    if (col < 0 || row < 0 || row >= rows()) return std::numeric_limits<double>::quiet_NaN();
    const auto& r = cells[static_cast<size_t>(row)];
    if (static_cast<size_t>(col) >= r.size()) return std::numeric_limits<double>::quiet_NaN();
    const std::string& s = r[static_cast<size_t>(col)];
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end == s.c_str()) return std::numeric_limits<double>::quiet_NaN();
    return v;
  }
  // Throws naming the file when the column is missing.
  std::vector<double> column(const std::string& name) const {
    const int c = col(name);
    if (c < 0) throw std::runtime_error(source + ": no column '" + name + "'");
    std::vector<double> v(static_cast<size_t>(rows()));
    for (long r = 0; r < rows(); ++r) v[static_cast<size_t>(r)] = num(r, c);
    return v;
  }
};

// Comma-separated, first line the header, no quoting (capflow writes none). Blank lines are
// skipped; a row with fewer cells than the header (a line being written) is dropped.
inline Table read_csv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path);
  Table t;
  t.source = path;
  std::string line;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::string cell;
    std::istringstream in(l);
    while (std::getline(in, cell, ',')) {
      while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
      size_t b = 0;
      while (b < cell.size() && cell[b] == ' ') ++b;
      out.push_back(cell.substr(b));
    }
    if (!l.empty() && l.back() == ',') out.emplace_back();
    return out;
  };
  if (!std::getline(f, line)) throw std::runtime_error(path + ": empty file (no header)");
  t.header = split(line);
  while (std::getline(f, line)) {
    if (line.empty() || line == "\r") continue;
    auto cells = split(line);
    if (cells.size() < t.header.size()) continue;
    t.cells.push_back(std::move(cells));
  }
  return t;
}

// ---------------------------------------------------------------- profiles

struct Profile {
  std::string file;
  long index = -1;  // NNNNNN of profile_NNNNNN.csv (= the frame index)
  double t = 0;
  std::vector<std::pair<double, double>> z;  // plane z = z_c: (x, y)
  std::vector<std::pair<double, double>> y;  // plane y = y_c: (x, z)
};

inline Profile read_profile(const std::string& path) {
  const Table tb = read_csv(path);
  const int cp = tb.col("plane"), ct = tb.col("t"), ca = tb.col("a"), cb = tb.col("b");
  if (cp < 0 || ct < 0 || ca < 0 || cb < 0)
    throw std::runtime_error(path + ": header must be plane,t,a,b");
  Profile p;
  p.file = path;
  p.t = std::numeric_limits<double>::quiet_NaN();
  for (long r = 0; r < tb.rows(); ++r) {
    const std::string& plane = tb.cells[static_cast<size_t>(r)][static_cast<size_t>(cp)];
    const double a = tb.num(r, ca), b = tb.num(r, cb);
    if (!std::isfinite(a) || !std::isfinite(b)) continue;
    if (std::isnan(p.t)) p.t = tb.num(r, ct);
    if (plane == "z")
      p.z.emplace_back(a, b);
    else if (plane == "y")
      p.y.emplace_back(a, b);
  }
  if (std::isnan(p.t)) throw std::runtime_error(path + ": no profile points");
  const std::string stem = fs::path(path).stem().string();  // profile_NNNNNN
  const auto us = stem.rfind('_');
  if (us != std::string::npos) p.index = std::atol(stem.c_str() + us + 1);
  return p;
}

// (index, t, path) of every readable profile file, sorted by index.
struct ProfileRef {
  long index;
  double t;
  std::string file;
};
inline std::vector<ProfileRef> list_profiles(const std::string& run_dir) {
  std::vector<ProfileRef> out;
  const fs::path d = fs::path(run_dir) / "profiles";
  if (!fs::is_directory(d)) return out;
  for (const auto& e : fs::directory_iterator(d)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("profile_", 0) != 0 || e.path().extension() != ".csv") continue;
    try {
      const Profile p = read_profile(e.path().string());
      out.push_back({p.index, p.t, e.path().string()});
    } catch (const std::exception&) {
      // A file being written (or damaged) is left out.
    }
  }
  std::sort(out.begin(), out.end(),
            [](const ProfileRef& a, const ProfileRef& b) { return a.index < b.index; });
  return out;
}

// Index of the value in `ts` nearest to t (first of equals); -1 for an empty list.
inline long nearest(const std::vector<double>& ts, double t) {
  long best = -1;
  for (size_t i = 0; i < ts.size(); ++i)
    if (best < 0 || std::abs(ts[i] - t) < std::abs(ts[static_cast<size_t>(best)] - t))
      best = static_cast<long>(i);
  return best;
}

// ---------------------------------------------------------------- surfaces

// The scalars a surface file carries in its FieldData: Ca and the snapshot's diagnostics.
inline std::map<std::string, double> snapshot_field_scalars(const render::Snapshot& s) {
  return {{"ca", s.ca},
          {"D", s.diag.D},
          {"L", s.diag.L},
          {"S", s.diag.S},
          {"W", s.diag.W},
          {"tau_max", s.diag.tau_max},
          {"tau_min", s.diag.tau_min}};
}

inline output::VtkSurface vtk_from_snapshot(const render::Snapshot& s) {
  output::VtkSurface v;
  v.ne = s.ne;
  v.n = s.nb;
  v.time = s.time;
  v.x = s.x;
  if (!s.tau1.empty()) {
    v.point_arrays["tau1"] = {1, s.tau1};
    v.point_arrays["tau2"] = {1, s.tau2};
  }
  v.field_scalars = snapshot_field_scalars(s);
  return v;
}

inline render::Snapshot snapshot_from_vtk(const output::VtkSurface& v) {
  render::Snapshot s;
  s.ne = v.ne;
  s.nb = v.n;
  s.x = v.x;
  s.time = v.time;
  auto scalar = [&](const char* name) -> const std::vector<double>* {
    auto it = v.point_arrays.find(name);
    return it != v.point_arrays.end() && it->second.components == 1 ? &it->second.values : nullptr;
  };
  if (const auto* t1 = scalar("tau1")) {
    s.tau1 = *t1;
    const auto* t2 = scalar("tau2");
    s.tau2 = t2 ? *t2 : *t1;
  }
  auto field = [&](const char* name, double dflt) {
    auto it = v.field_scalars.find(name);
    return it == v.field_scalars.end() ? dflt : it->second;
  };
  s.ca = field("ca", 0);
  s.diag.D = field("D", 0);
  s.diag.L = field("L", 0);
  s.diag.S = field("S", 0);
  s.diag.W = field("W", 0);
  double tmax = 0, tmin = 0;
  if (!s.tau1.empty()) {
    tmax = *std::max_element(s.tau1.begin(), s.tau1.end());
    tmin = *std::min_element(s.tau2.begin(), s.tau2.end());
  }
  s.diag.tau_max = field("tau_max", tmax);
  s.diag.tau_min = field("tau_min", tmin);
  return s;
}

// (time, path) of every saved surface of a run: the entries of <run>/surface.pvd when it
// exists (files that are missing are left out), else every vtk/*.vtp (time = its TimeValue).
inline std::vector<std::pair<double, std::string>> list_surfaces(const std::string& run_dir) {
  std::vector<std::pair<double, std::string>> out;
  const fs::path pvd = fs::path(run_dir) / kSurfaceCollection;
  if (fs::exists(pvd)) {
    try {
      for (const auto& e : output::PvdCollection::read(pvd.string())) {
        const fs::path f = fs::path(run_dir) / e.file;
        if (fs::exists(f)) out.emplace_back(e.time, f.string());
      }
      return out;
    } catch (const std::exception&) {
      out.clear();  // fall back to the files themselves
    }
  }
  const fs::path d = fs::path(run_dir) / "vtk";
  if (!fs::is_directory(d)) return out;
  for (const auto& e : fs::directory_iterator(d)) {
    if (e.path().extension() != ".vtp") continue;
    try {
      out.emplace_back(output::read_vtp(e.path().string()).time, e.path().string());
    } catch (const std::exception&) {
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The saved surface of `run_dir` nearest in time to t, as a render::Snapshot (positions,
// tensions, t, Ca and the diagnostics stored with it; out->time is the time found). Returns
// false when the run has no readable surface file; *note (optional) says which file was used
// or why none was.
inline bool load_surface(const std::string& run_dir, double t, render::Snapshot* out,
                         std::string* note = nullptr) {
  auto say = [&](const std::string& m) {
    if (note) *note = m;
  };
  auto list = list_surfaces(run_dir);
  if (list.empty()) {
    say("no surface data (" + std::string(kSurfaceCollection) + " or vtk/*.vtp) in " + run_dir);
    return false;
  }
  std::vector<double> ts;
  for (const auto& e : list) ts.push_back(e.first);
  // Try the nearest first, then the others by distance (a file may be unreadable).
  std::vector<size_t> order(list.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return std::abs(ts[a] - t) < std::abs(ts[b] - t); });
  std::string errors;
  for (size_t i : order) {
    try {
      const output::VtkSurface v = output::read_vtp(list[i].second);
      render::Snapshot s = snapshot_from_vtk(v);
      std::string err;
      if (!s.IsValid(&err)) throw std::runtime_error(err);
      *out = std::move(s);
      say("surface " + list[i].second);
      return true;
    } catch (const std::exception& e) {
      errors += std::string(errors.empty() ? "" : "; ") + e.what();
    }
  }
  say("no readable surface file in " + run_dir + ": " + errors);
  return false;
}

}  // namespace capflow::app::figures
