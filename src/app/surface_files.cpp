// capflow/app/surface_files: see surface_files.h.
#include "app/surface_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace capflow::app {

namespace fs = std::filesystem;

std::string surface_file_name(long index) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "vtk/surface_%06ld.vtp", index);
  return buf;
}

std::map<std::string, double> snapshot_field_scalars(const render::Snapshot& s) {
  return {{"ca", s.ca},
          {"D", s.diag.D},
          {"L", s.diag.L},
          {"S", s.diag.S},
          {"W", s.diag.W},
          {"tau_max", s.diag.tau_max},
          {"tau_min", s.diag.tau_min}};
}

output::VtkSurface vtk_from_snapshot(const render::Snapshot& s) {
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

render::Snapshot snapshot_from_vtk(const output::VtkSurface& v) {
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
  if (const auto* h = scalar("mean_curvature")) s.curvature = *h;
  if (const auto* w = scalar("bending_energy_density")) s.bending = *w;
  if (auto it = v.point_arrays.find("velocity");
      it != v.point_arrays.end() && it->second.components == 3) {
    const std::vector<double>& u = it->second.values;
    s.speed.resize(u.size() / 3);
    for (size_t k = 0; k < s.speed.size(); ++k)
      s.speed[k] = std::sqrt(u[3 * k] * u[3 * k] + u[3 * k + 1] * u[3 * k + 1] +
                             u[3 * k + 2] * u[3 * k + 2]);
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

std::vector<std::pair<double, std::string>> list_surfaces(const std::string& run_dir) {
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

bool load_surface(const std::string& run_dir, double t, render::Snapshot* out, std::string* note) {
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

}  // namespace capflow::app
