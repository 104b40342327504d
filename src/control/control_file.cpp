#include "control/control_file.h"
#include "control/stability.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <tuple>

#include "control/json_input.h"
#include "control/limits.h"
#include "control/schedule.h"
#include "control/schema_table.h"
#include "geometry/mesh.h"

namespace capflow::control {

using json = nlohmann::json;

using schema::Field;
using schema::Group;
using schema::show;

namespace {

// time.dt warns above this fraction of the fitted stability limit (control/stability.h: the fit
// is within 5 % of every measured limit).
constexpr double kStabilityMargin = 0.9;

// The value at a dotted path of `doc`, or nullptr when absent (or a parent is not an object).
const json* lookup(const json& doc, const std::string& path) {
  const json* j = &doc;
  for (size_t s = 0, e; s <= path.size(); s = e + 1) {
    e = path.find('.', s);
    if (e == std::string::npos) e = path.size();
    if (!j->is_object()) return nullptr;
    const auto it = j->find(path.substr(s, e - s));
    if (it == j->end()) return nullptr;
    j = &*it;
  }
  return j;
}

// Every key of `j` (the object at `prefix`) must be a field or a group of the schema; groups
// must be objects (or true/false where the group has a toggle).
void check_keys(const json& j, const std::string& prefix, std::vector<ControlIssue>* errors) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string path = prefix.empty() ? it.key() : prefix + "." + it.key();
    if (schema::find_field(path)) continue;
    if (const Group* g = schema::find_group(path)) {
      if (it->is_object()) {
        check_keys(*it, path, errors);
      } else if (!(g->set_toggle && it->is_boolean())) {
        errors->push_back({path, std::string("expected ") +
                                     (g->set_toggle ? "true, false or " : "an ") +
                                     "object {...}, got " + show(*it)});
      }
      continue;
    }
    const std::vector<std::string> names = schema::names_under(prefix);
    const std::string sug = schema::suggestion(it.key(), names);
    std::string valid;
    for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + n;
    errors->push_back({path, "unknown key" +
                                 (sug.empty() ? "" : " (did you mean \"" + sug + "\"?)") +
                                 "; valid keys here: " + valid});
  }
}

// Rules that involve more than one field.
void check_combinations(const json& doc, ControlOptions& o, std::vector<ControlIssue>* errors) {
  if (!lookup(doc, "ca"))
    errors->push_back({"ca",
                       "missing: give a capillary number (e.g. \"ca\": 0.45) or a schedule "
                       "(a list of segments)"});
  if (!lookup(doc, "mesh.division"))
    o.mesh.division = default_division(o.mesh.elements, o.flow.type);
  if (o.mesh.division == geometry::Division::Diagonal && o.mesh.elements != 6)
    errors->push_back({"mesh.division",
                       "value \"diagonal\" needs 6 elements (the turned cube), got "
                       "mesh.elements " +
                           std::to_string(o.mesh.elements)});
  const json* type = lookup(doc, "flow.type");
  const bool custom = type && type->is_string() && type->get<std::string>() == "custom";
  if (custom && !lookup(doc, "flow.gradient"))
    errors->push_back({"flow.gradient",
                       "missing: \"type\": \"custom\" needs the velocity gradient G "
                       "(u = G x) as 3 rows of 3 numbers, e.g. [[1, 0, 0], [0, -0.5, "
                       "0], [0, 0, -0.5]]"});
  if (lookup(doc, "flow.gradient") && !custom)  // (also when "type" is missing: planar extension)
    errors->push_back({"flow.gradient",
                       "only with \"type\": \"custom\" (planar extension and simple "
                       "shear have their own gradients)"});
  if (o.render.width % 2)
    errors->push_back({"render.width", "value " + std::to_string(o.render.width) +
                                           " is odd: movies need even sizes"});
  if (o.render.height % 2)
    errors->push_back({"render.height", "value " + std::to_string(o.render.height) +
                                            " is odd: movies need even sizes"});
  if (o.output.vtk_points == 1)
    errors->push_back({"output.vtk_points",
                       "value 1 is not valid: 0 (the nodes) or 2 to 64 points per element edge"});
  const std::vector<ControlIssue> t = time_issues(o.time, 0.0);
  errors->insert(errors->end(), t.begin(), t.end());
  // From rest the levels start at Ca = 0; after start.from at the source's Ca (checked when the
  // source is read: CaScheduler).
  const std::vector<ControlIssue> levels = level_count_issues(
      o.ca, o.start.from.empty() ? std::optional<double>(0.0) : std::nullopt);
  errors->insert(errors->end(), levels.begin(), levels.end());
}

// Legal but suspicious values.
void add_warnings(const json& doc, const ControlOptions& o, std::vector<ControlIssue>* warnings) {
  if (lookup(doc, "capsule.C") && o.law.kind != membrane::LawKind::Skalak)
    warnings->push_back({"capsule.C", "ignored: C applies to the Skalak law only"});
  if (lookup(doc, "capsule.psi") && o.law.kind != membrane::LawKind::MooneyRivlin)
    warnings->push_back({"capsule.psi", "ignored: psi applies to the Mooney-Rivlin law only"});
  double ca_min = std::numeric_limits<double>::infinity();
  for (const auto& s : o.ca.segments)
    ca_min = std::min(ca_min, s.kind == CaSegment::Kind::Hold ? s.ca : s.to);
  if (!o.time.adaptive && std::isfinite(ca_min)) {
    const double limit = fixed_step_limit(o.mesh, o.law.kind, ca_min);
    if (o.time.dt > kStabilityMargin * limit) {
      std::ostringstream s;
      s << "dt = " << o.time.dt << " is above " << kStabilityMargin * 100
        << " % of the measured stability limit of fixed RK4 steps for this mesh and law at the "
           "smallest Ca of the schedule, "
        << ca_min << ": about " << limit
        << " (docs/performance.md, \"Fixed steps: the stability limit\"): the run will likely "
           "fail its health check; \"auto\" steps find the limit themselves";
      warnings->push_back({"time.dt", s.str()});
    }
  }
  if (o.flow.type == capsule::FlowType::PlanarExtension && o.mesh.elements != 14 &&
      o.mesh.division == geometry::Division::Cube)
    warnings->push_back(
        {"mesh.division", std::string("\"cube\" with ") + std::to_string(o.mesh.elements) +
                              " elements: in planar extension the capsule's tips (+-x) lie in "
                              "the middle of a 90-degree cap element, whose resolution limits "
                              "volume conservation and stability (Skalak Ca=0.45, NB=8, t=1: "
                              "drift -1.8e-4 / -1.9e-4 on the NE=6 / NE=10 cube, -3.8e-6 / "
                              "-1.9e-6 with the default division \"diagonal\" / \"box\", "
                              "-3.9e-7 at NE=14)"});
  if (!o.numerics.smoothing)
    warnings->push_back({"numerics.smoothing",
                         "false: without the membrane smoothing the "
                         "method is unstable (paper fig. 2a)"});
  if (o.output.frame_every > 0 && !o.output.png && !o.output.mp4.enabled)
    warnings->push_back({"output.frame_every", "frames are taken but neither png nor mp4 is on"});
}

}  // namespace

ControlError::ControlError(const std::string& source, std::vector<ControlIssue> issues)
    : std::runtime_error([&] {
        std::string m = source + ": " + std::to_string(issues.size()) +
                        (issues.size() == 1 ? " problem" : " problems");
        for (const auto& i : issues) m += "\n  " + i.str();
        return m;
      }()),
      issues_(std::move(issues)) {}

capsule::DynamicsOptions dynamics_options(const ControlOptions& o) {
  capsule::DynamicsOptions d;
  d.viscosity_ratio = o.viscosity_ratio;
  // The viscosity-ratio solve three decades below the tolerances its velocities feed: the
  // adaptive steps' local error and capflow steady's residual (and never looser than 1e-8).
  d.krylov_tolerance = std::min(1e-8, 1e-3 * std::min(o.time.tolerance, o.steady.solve_tolerance));
  d.smooth_geometry = d.smooth_traction = o.numerics.smoothing;
  d.volume_correction = o.numerics.volume_correction;
  d.symmetry = o.numerics.symmetry ? capsule::SymmetryChoice::Auto : capsule::SymmetryChoice::None;
  d.quadrature_scale = o.numerics.quadrature_scale;
  d.shape = o.shape;
  d.bending = o.bending;
  return d;
}

std::unique_ptr<geometry::Mesh> make_mesh(const MeshOptions& m) {
  return std::make_unique<geometry::Mesh>(m.elements, m.nb, geometry::ElementMap::Equiangular,
                                          m.division);
}

double min_node_spacing(const MeshOptions& options) {
  // Cached per mesh: every parse (and every live edit) asks for it, and building the mesh is the
  // slowest part of parsing.
  static std::mutex mu;
  static std::map<std::tuple<int, int, int>, double> cache;
  const auto key =
      std::make_tuple(options.elements, options.nb, static_cast<int>(options.division));
  {
    std::lock_guard<std::mutex> l(mu);
    const auto it = cache.find(key);
    if (it != cache.end()) return it->second;
  }
  const int nb = options.nb;
  const std::unique_ptr<geometry::Mesh> owned = make_mesh(options);
  const geometry::Mesh& mesh = *owned;
  double d = std::numeric_limits<double>::infinity();
  const auto& x = mesh.reference();
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i + 1 < nb; ++i) {
        d = std::min(d, (x.col(mesh.local(e, i + 1, j)) - x.col(mesh.local(e, i, j))).norm());
        d = std::min(d, (x.col(mesh.local(e, j, i + 1)) - x.col(mesh.local(e, j, i))).norm());
      }
  std::lock_guard<std::mutex> l(mu);
  cache[key] = d;
  return d;
}

std::string to_string(RunState s) {
  switch (s) {
    case RunState::Running:
      return "running";
    case RunState::Paused:
      return "paused";
    case RunState::Stopped:
      return "stopped";
  }
  return "running";
}

std::vector<ControlIssue> time_issues(const TimeOptions& time, double t_now) {
  std::vector<ControlIssue> out;
  std::ostringstream m;
  if (time.adaptive) {
    if (!(time.t_end > t_now)) {
      m << "value " << time.t_end << " is not after the run's time t = " << t_now
        << ": nothing would be simulated";
      out.push_back({"time.t_end", m.str()});
    }
    return out;
  }
  if (time.t_end < (t_now > 0 ? t_now + 0.5 * time.dt : time.dt)) {
    if (t_now > 0)
      m << "value " << time.t_end << " is not after the run's time t = " << t_now
        << " (by at least half a step, dt = " << time.dt << "): nothing would be simulated";
    else
      m << "value " << time.t_end << " is below the time step dt = " << time.dt
        << ": not one step would be taken (t_end must be at least dt)";
    out.push_back({"time.t_end", m.str()});
  } else if ((time.t_end - t_now) / time.dt > kMaxSteps) {
    m << "value " << time.t_end << " asks for " << (time.t_end - t_now) / time.dt
      << " steps of dt = " << time.dt << ": at most " << kMaxSteps
      << " steps are allowed (raise dt or lower t_end)";
    out.push_back({"time.t_end", m.str()});
  }
  return out;
}

ParsedControl parse_control(const std::string& text, const std::string& source) {
  const json doc = parse_json_strict(text, source);
  if (!doc.is_object())
    throw ControlError(source,
                       {{"", "the control file must be a JSON object {...}, got " + show(doc)}});
  std::vector<ControlIssue> errors;
  ParsedControl out;
  check_keys(doc, "", &errors);
  schema::ReadContext ctx{out.options, errors, out.warnings};
  for (const Field& f : schema::fields())
    if (const json* v = lookup(doc, f.info.path)) f.read(*v, ctx);
  for (const Group& g : schema::groups())
    if (g.set_toggle)
      if (const json* v = lookup(doc, g.path)) {
        if (v->is_boolean()) g.set_toggle(out.options, v->get<bool>());
        if (v->is_object()) g.set_toggle(out.options, true);
      }
  check_combinations(doc, out.options, &errors);
  if (!errors.empty()) throw ControlError(source, errors);
  add_warnings(doc, out.options, &out.warnings);
  return out;
}

std::optional<RunOptions> run_keys_of(const std::string& text) {
  json doc;
  try {
    doc = parse_json_strict(text, "control file");
  } catch (const ControlError&) {
    return std::nullopt;
  }
  const json* run = lookup(doc, "run");
  if (!run || !run->is_object()) return std::nullopt;
  try {
    return parse_control(json{{"ca", 1.0}, {"run", *run}}.dump()).options.run;
  } catch (const ControlError&) {
    return std::nullopt;
  }
}

ParsedControl load_control_file(const std::string& path) {
  return parse_control(read_control_text(path), path);
}

std::string to_json_text(const ControlOptions& o) {
  json j = json::object();
  for (const Field& f : schema::fields()) {
    const std::optional<json> v = f.write(o);
    if (v)
      j[json::json_pointer("/" + [&] {
        std::string p = f.info.path;
        for (char& c : p)
          if (c == '.') c = '/';
        return p;
      }())] = *v;
  }
  for (const Group& g : schema::groups())
    if (g.toggle && !g.toggle(o)) {
      std::string p = g.path;
      for (char& c : p)
        if (c == '.') c = '/';
      j[json::json_pointer("/" + p)] = false;
    }
  return j.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace capflow::control
