#include "control/edit.h"

#include <nlohmann/json.hpp>

#include "control/control_file.h"

namespace capflow::control {

using json = nlohmann::json;

namespace {

const char* const kFrozen[] = {"capsule", "mesh", "start", "flow", "numerics.symmetry", "numerics.smoothing",
                               "numerics.quadrature_scale",
                               "output.dir", "output.png", "output.mp4", "render"};

bool frozen(const std::string& path) {
  for (const char* f : kFrozen) {
    const std::string p(f);
    if (path == p || path.rfind(p + ".", 0) == 0) return true;
  }
  return false;
}

// Leaf differences between two documents ("ca" compared as a whole).
void diff(const json& a, const json& b, const std::string& path, std::vector<OptionChange>* out) {
  if (a.is_object() && b.is_object() && path != "ca") {
    for (auto it = a.begin(); it != a.end(); ++it) {
      const std::string p = path.empty() ? it.key() : path + "." + it.key();
      if (b.contains(it.key()))
        diff(it.value(), b[it.key()], p, out);
      else
        out->push_back({p, it.value().dump(), "null", ""});
    }
    for (auto it = b.begin(); it != b.end(); ++it)
      if (!a.contains(it.key()))
        out->push_back({path.empty() ? it.key() : path + "." + it.key(), "null", it.value().dump(), ""});
    return;
  }
  if (a != b) out->push_back({path, a.dump(), b.dump(), ""});
}

}  // namespace

EditResult apply_edit(const ControlOptions& current, const ControlOptions& edited) {
  EditResult r;
  const json a = json::parse(to_json_text(current));
  const json b = json::parse(to_json_text(edited));
  std::vector<OptionChange> changes;
  diff(a, b, "", &changes);
  r.merged = current;
  for (OptionChange& c : changes) {
    if (frozen(c.path)) {
      c.reason = "cannot change while the run goes on (restart the run to change it)";
      r.refused.push_back(c);
      continue;
    }
    r.applied.push_back(c);
    const std::string& p = c.path;
    if (p == "ca") {
      r.merged.ca = edited.ca;
      r.schedule_changed = true;
    } else if (p.rfind("steady.", 0) == 0) {
      r.merged.steady = edited.steady;
      r.schedule_changed = true;
    } else if (p == "time.dt") {
      r.merged.time.dt = edited.time.dt;
    } else if (p == "time.t_end") {
      r.merged.time.t_end = edited.time.t_end;
    } else if (p == "output.csv_every") {
      r.merged.output.csv_every = edited.output.csv_every;
    } else if (p == "output.frame_every") {
      r.merged.output.frame_every = edited.output.frame_every;
    } else if (p == "output.checkpoint_every") {
      r.merged.output.checkpoint_every = edited.output.checkpoint_every;
    } else if (p == "output.vtk_every") {
      r.merged.output.vtk_every = edited.output.vtk_every;
    } else if (p == "numerics.volume_correction") {
      r.merged.numerics.volume_correction = edited.numerics.volume_correction;
    } else if (p == "numerics.threads") {
      r.merged.numerics.threads = edited.numerics.threads;
    } else if (p == "run.state") {
      r.merged.run.state = edited.run.state;
    } else if (p == "run.checkpoint_now") {
      r.merged.run.checkpoint_now = edited.run.checkpoint_now;
    } else {
      // A key this policy does not know: refuse rather than half-apply.
      r.applied.pop_back();
      c.reason = "not changeable mid-run";
      r.refused.push_back(c);
    }
  }
  return r;
}

}  // namespace capflow::control
