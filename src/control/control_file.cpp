#include "control/control_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "geometry/mesh.h"

namespace capflow::control {

using json = nlohmann::json;

namespace {

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

std::string quoted_list(const std::vector<std::string>& v) {
  std::vector<std::string> q;
  for (const auto& s : v) q.push_back("\"" + s + "\"");
  return join(q);
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1,
                         prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string suggestion(const std::string& word, const std::vector<std::string>& options) {
  std::string best;
  size_t best_d = std::numeric_limits<size_t>::max();
  for (const auto& o : options) {
    const size_t d = edit_distance(word, o);
    if (d < best_d) {
      best_d = d;
      best = o;
    }
  }
  if (best_d <= std::max<size_t>(2, word.size() / 3)) return best;
  return "";
}

std::string show(const json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool contains(double v) const {
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
  }
  std::string text() const {
    std::ostringstream s;
    s << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
    return s.str();
  }
};
Range closed(double lo, double hi) { return {lo, hi, false, false}; }
Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }

// Reads one JSON object, remembering which keys were used; finish() reports the others.
class Reader {
 public:
  Reader(const json* j, std::string path, std::vector<ControlIssue>* errors)
      : j_(j), path_(std::move(path)), errors_(errors) {}

  std::string at(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const json* get(const std::string& key) {
    known_.push_back(key);
    if (!j_ || !j_->is_object()) return nullptr;
    auto it = j_->find(key);
    return it == j_->end() ? nullptr : &*it;
  }
  void error(const std::string& key, const std::string& msg) {
    errors_->push_back({key.empty() ? path_ : at(key), msg});
  }

  void number(const std::string& key, double* out, const Range& r, const std::string& meaning) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_number()) {
      error(key, "expected a number (" + meaning + " in " + r.text() + "), got " + show(*v));
      return;
    }
    const double d = v->get<double>();
    if (!std::isfinite(d) || !r.contains(d)) {
      std::ostringstream s;
      s << "value " << show(*v) << " is out of range: " << meaning << " must be in " << r.text();
      error(key, s.str());
      return;
    }
    *out = d;
  }

  void integer(const std::string& key, int* out, int lo, int hi, const std::string& meaning) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_number_integer()) {
      error(key, "expected an integer (" + meaning + ", " + std::to_string(lo) + ".." +
                     std::to_string(hi) + "), got " + show(*v));
      return;
    }
    const long long i = v->get<long long>();
    if (i < lo || i > hi) {
      error(key, "value " + show(*v) + " is out of range: " + meaning + " must be in " +
                     std::to_string(lo) + ".." + std::to_string(hi));
      return;
    }
    *out = static_cast<int>(i);
  }

  void integer_of(const std::string& key, int* out, const std::vector<int>& allowed,
                  const std::string& meaning) {
    const json* v = get(key);
    if (!v) return;
    std::vector<std::string> a;
    for (int x : allowed) a.push_back(std::to_string(x));
    if (!v->is_number_integer() ||
        std::find(allowed.begin(), allowed.end(), v->get<long long>()) == allowed.end()) {
      error(key, "value " + show(*v) + " is not allowed: " + meaning + " must be one of " +
                     join(a));
      return;
    }
    *out = v->get<int>();
  }

  void boolean(const std::string& key, bool* out) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_boolean()) {
      error(key, "expected true or false, got " + show(*v));
      return;
    }
    *out = v->get<bool>();
  }

  void text(const std::string& key, std::string* out, const std::string& meaning) {
    const json* v = get(key);
    if (!v) return;
    if (!v->is_string() || v->get<std::string>().empty()) {
      error(key, "expected a non-empty string (" + meaning + "), got " + show(*v));
      return;
    }
    *out = v->get<std::string>();
  }

  // Returns the index of the chosen alternative, or -1 (missing or invalid).
  int choice(const std::string& key, const std::vector<std::string>& alternatives) {
    const json* v = get(key);
    if (!v) return -1;
    if (v->is_string()) {
      const std::string s = v->get<std::string>();
      for (size_t i = 0; i < alternatives.size(); ++i)
        if (s == alternatives[i]) return static_cast<int>(i);
      const std::string sug = suggestion(s, alternatives);
      error(key, "value " + show(*v) + " is not one of " + quoted_list(alternatives) +
                     (sug.empty() ? "" : " (did you mean \"" + sug + "\"?)"));
      return -1;
    }
    error(key, "expected one of " + quoted_list(alternatives) + ", got " + show(*v));
    return -1;
  }

  // A nested object (nullptr-backed when absent, so defaults stay).
  Reader object(const std::string& key) {
    const json* v = get(key);
    if (v && !v->is_object()) {
      error(key, "expected an object {...}, got " + show(*v));
      return Reader(nullptr, at(key), errors_);
    }
    return Reader(v, at(key), errors_);
  }

  bool present(const std::string& key) const { return j_ && j_->is_object() && j_->contains(key); }

  void finish() {
    if (!j_ || !j_->is_object()) return;
    for (auto it = j_->begin(); it != j_->end(); ++it) {
      if (std::find(known_.begin(), known_.end(), it.key()) != known_.end()) continue;
      const std::string sug = suggestion(it.key(), known_);
      errors_->push_back({at(it.key()), "unknown key" +
                                            (sug.empty() ? "" : " (did you mean \"" + sug + "\"?)") +
                                            "; valid keys here: " + join(known_)});
    }
  }

 private:
  const json* j_;
  std::string path_;
  std::vector<ControlIssue>* errors_;
  std::vector<std::string> known_;
};

// flow.gradient: 3 rows of 3 finite numbers, |G_ij| <= 100, not all zero, trace within 1e-9 of
// the largest entry (then removed from the diagonal: Flow::custom needs it exact).
bool read_gradient(const json& v, Reader& r, capsule::Flow* flow) {
  auto error = [&r](const std::string& m) { r.error("gradient", m); };
  Eigen::Matrix3d g;
  const bool shape = v.is_array() && v.size() == 3 &&
                     std::all_of(v.begin(), v.end(), [](const json& row) {
                       return row.is_array() && row.size() == 3 &&
                              std::all_of(row.begin(), row.end(),
                                          [](const json& x) { return x.is_number(); });
                     });
  if (!shape) {
    error("expected 3 rows of 3 numbers (the velocity gradient G, u = G x), got " + show(v));
    return false;
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      g(i, j) = v[i][j].get<double>();
      if (!std::isfinite(g(i, j)) || std::abs(g(i, j)) > 100) {
        error("entry [" + std::to_string(i) + "][" + std::to_string(j) + "] = " + show(v[i][j]) +
              " is out of range: every entry must be in [-100, 100]");
        return false;
      }
    }
  const double big = g.cwiseAbs().maxCoeff();
  if (big == 0) {
    error("is zero: give a nonzero gradient (its scale sets the time unit and Ca)");
    return false;
  }
  if (std::abs(g.trace()) > 1e-9 * big) {
    std::ostringstream m;
    m << "has trace " << g.trace() << ": the flow must be incompressible, G00 + G11 + G22 = 0";
    error(m.str());
    return false;
  }
  g.diagonal().array() -= g.trace() / 3;
  *flow = capsule::Flow::custom(g);
  return true;
}

// "hold": "steady" or a duration.
void read_hold(Reader& r, CaSegment* s) {
  const json* v = r.get("hold");
  if (!v) return;
  if (v->is_string() && v->get<std::string>() == "steady") {
    s->until_steady = true;
  } else if (v->is_number() && v->get<double>() > 0 && v->get<double>() <= 1e6) {
    s->until_steady = false;
    s->hold_time = v->get<double>();
  } else {
    r.error("hold", "value " + show(*v) + " is not valid: hold must be \"steady\" or a time in (0, 1e6]");
  }
}

const Range kCaRange = open_closed(0.0, 100.0);

void read_schedule(const json& v, std::vector<ControlIssue>* errors, CaSchedule* out) {
  out->segments.clear();
  if (v.is_number()) {
    CaSegment s;
    s.ca = v.get<double>();
    if (!kCaRange.contains(s.ca)) {
      errors->push_back({"ca", "value " + show(v) + " is out of range: Ca must be in " + kCaRange.text()});
      return;
    }
    out->constant = true;
    out->segments.push_back(s);
    return;
  }
  if (!v.is_array() || v.empty()) {
    errors->push_back({"ca", "expected a number (constant Ca) or a non-empty list of segments "
                             "({\"ca\": x, \"hold\": ...}, {\"ramp\": {...}}, {\"steps\": {...}}), got " +
                                 show(v)});
    return;
  }
  out->constant = false;
  double level = -1;  // Ca at the end of the previous segment
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string path = "ca[" + std::to_string(i) + "]";
    Reader r(&v[i], path, errors);
    if (!v[i].is_object()) {
      errors->push_back({path, "expected an object, got " + show(v[i])});
      continue;
    }
    CaSegment s;
    const int kinds = r.present("ca") + r.present("ramp") + r.present("steps");
    if (kinds != 1) {
      errors->push_back({path, "a segment needs exactly one of \"ca\" (hold a level), \"ramp\" or "
                               "\"steps\", got " + show(v[i])});
      continue;
    }
    const size_t before = errors->size();
    if (r.present("ca")) {
      s.kind = CaSegment::Kind::Hold;
      s.ca = -1;
      r.number("ca", &s.ca, kCaRange, "Ca");
      read_hold(r, &s);
      level = s.ca;
    } else if (r.present("ramp")) {
      s.kind = CaSegment::Kind::Ramp;
      Reader q = r.object("ramp");
      s.to = -1;
      q.number("to", &s.to, kCaRange, "the final Ca");
      q.number("rate", &s.rate, open_closed(0.0, 1e3), "|dCa/dt|");
      if (!q.present("to")) q.error("", "missing \"to\" (the final Ca)");
      if (!q.present("rate")) q.error("", "missing \"rate\" (|dCa/dt| > 0)");
      q.finish();
      if (errors->size() == before && level < 0)
        errors->push_back({path, "a ramp needs a starting level: put a {\"ca\": x, ...} segment before it"});
      level = s.to;
    } else {
      s.kind = CaSegment::Kind::Steps;
      Reader q = r.object("steps");
      s.to = -1;
      q.number("to", &s.to, kCaRange, "the final Ca");
      q.number("by", &s.by, open_closed(0.0, 100.0), "the increment");
      read_hold(q, &s);
      if (!q.present("to")) q.error("", "missing \"to\" (the final Ca)");
      if (!q.present("by")) q.error("", "missing \"by\" (the increment, > 0)");
      q.finish();
      if (errors->size() == before && level < 0)
        errors->push_back({path, "steps need a starting level: put a {\"ca\": x, ...} segment before them"});
      level = s.to;
    }
    r.finish();
    out->segments.push_back(s);
  }
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
  d.smooth_geometry = d.smooth_traction = o.numerics.smoothing;
  d.volume_correction = o.numerics.volume_correction;
  d.symmetry = o.numerics.symmetry ? capsule::SymmetryChoice::Auto : capsule::SymmetryChoice::None;
  d.quadrature_scale = o.numerics.quadrature_scale;
  return d;
}

std::unique_ptr<geometry::Mesh> make_mesh(const MeshOptions& m) {
  return std::make_unique<geometry::Mesh>(m.elements, m.nb, geometry::ElementMap::Equiangular,
                                          m.division);
}

double min_node_spacing(const MeshOptions& options) {
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
  return d;
}

std::string to_string(RunState s) {
  switch (s) {
    case RunState::Running: return "running";
    case RunState::Paused: return "paused";
    case RunState::Stopped: return "stopped";
  }
  return "running";
}

ParsedControl parse_control(const std::string& text, const std::string& source) {
  std::vector<ControlIssue> errors;
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    throw ControlError(source, {{"", std::string("not valid JSON: ") + e.what()}});
  }
  if (!doc.is_object())
    throw ControlError(source, {{"", "the control file must be a JSON object {...}, got " + show(doc)}});

  ParsedControl out;
  ControlOptions& o = out.options;
  Reader root(&doc, "", &errors);
  root.text("description", &o.description, "a free-text description of the run");

  {
    Reader r = root.object("capsule");
    const int law = r.choice("law", {"skalak", "neo-hookean", "mooney-rivlin"});
    if (law >= 0) o.law.kind = static_cast<membrane::LawKind>(law);
    r.number("C", &o.law.c, open_closed(-0.5, 1e4), "the Skalak area-dilatation parameter C");
    r.number("psi", &o.law.psi, closed(0.0, 1.0), "the Mooney-Rivlin parameter psi");
    r.number("viscosity_ratio", &o.viscosity_ratio, open_closed(0.0, 1e4), "the viscosity ratio");
    if (o.viscosity_ratio != 1.0)
      r.error("viscosity_ratio", "value " + show(*r.get("viscosity_ratio")) +
                                     " is not supported yet: only 1 (equal viscosities) is "
                                     "implemented");
    if (r.present("C") && law >= 0 && o.law.kind != membrane::LawKind::Skalak)
      out.warnings.push_back({"capsule.C", "ignored: C applies to the Skalak law only"});
    if (r.present("psi") && law >= 0 && o.law.kind != membrane::LawKind::MooneyRivlin)
      out.warnings.push_back({"capsule.psi", "ignored: psi applies to the Mooney-Rivlin law only"});
    r.finish();
  }
  bool division_given = false;
  {
    Reader r = root.object("mesh");
    r.integer_of("elements", &o.mesh.elements, {6, 10, 14}, "the element division");
    r.integer("nb", &o.mesh.nb, 4, 24, "nodes per element direction");
    division_given = r.present("division");
    const int d = r.choice("division", {"cube", "box", "diagonal"});
    if (d >= 0) o.mesh.division = static_cast<geometry::Division>(d);
    if (o.mesh.division == geometry::Division::Diagonal && o.mesh.elements != 6)
      r.error("division", "value \"diagonal\" needs 6 elements (the turned cube), got "
                              "mesh.elements " + std::to_string(o.mesh.elements));
    r.finish();
  }
  {
    Reader r = root.object("start");
    r.text("from", &o.start.from, "a run directory or checkpoint file to start from");
    r.boolean("restore_volume", &o.start.restore_volume);
    r.finish();
  }
  {
    Reader r = root.object("flow");
    const int t = r.choice("type", {"planar-extension", "simple-shear", "custom"});
    if (t == 0) o.flow = capsule::Flow::planar_extension();
    if (t == 1) o.flow = capsule::Flow::simple_shear();
    const json* g = r.get("gradient");
    if (t == 2 && !g)
      r.error("gradient", "missing: \"type\": \"custom\" needs the velocity gradient G (u = G x) "
                          "as 3 rows of 3 numbers, e.g. [[1, 0, 0], [0, -0.5, 0], [0, 0, -0.5]]");
    if (g && t != 2)  // (also when "type" is missing: it would default to planar extension)
      r.error("gradient", "only with \"type\": \"custom\" (planar extension and simple shear "
                          "have their own gradients)");
    if (g && t == 2) {
      capsule::Flow f;
      if (read_gradient(*g, r, &f)) o.flow = f;
    }
    r.finish();
  }
  if (!division_given) o.mesh.division = default_division(o.mesh.elements, o.flow.type);
  {
    Reader r = root.object("time");
    r.number("dt", &o.time.dt, open_closed(0.0, 0.1), "the time step dt");
    r.number("t_end", &o.time.t_end, open_closed(0.0, 1e6), "the end time t_end");
    r.finish();
  }
  if (const json* ca = root.get("ca")) {
    read_schedule(*ca, &errors, &o.ca);
  } else {
    errors.push_back({"ca", "missing: give a capillary number (e.g. \"ca\": 0.45) or a schedule "
                            "(a list of segments)"});
  }
  {
    Reader r = root.object("steady");
    r.number("tolerance", &o.steady.tolerance, open_closed(0.0, 1.0), "the steady-state rate tolerance");
    r.number("window", &o.steady.window, open_closed(0.0, 100.0), "the steady-state window");
    r.number("min_hold", &o.steady.min_hold, closed(0.0, 1e4), "the minimum hold time");
    r.boolean("stop", &o.steady.stop);
    r.finish();
  }
  {
    Reader r = root.object("output");
    r.text("dir", &o.output.dir, "the run directory");
    r.number("csv_every", &o.output.csv_every, open_closed(0.0, 1e6), "the CSV cadence");
    r.number("frame_every", &o.output.frame_every, closed(0.0, 1e6), "the frame cadence (0: none)");
    r.boolean("png", &o.output.png);
    if (const json* mp4 = r.get("mp4")) {
      if (mp4->is_boolean()) {
        o.output.mp4.enabled = mp4->get<bool>();
      } else if (mp4->is_object()) {
        Reader m = r.object("mp4");
        o.output.mp4.enabled = true;
        m.integer("fps", &o.output.mp4.fps, 1, 240, "frames per second");
        m.integer("quality", &o.output.mp4.quality, 0, 51, "the x264 CRF (0 best, 51 worst)");
        m.finish();
      } else {
        r.error("mp4", "expected true, false or {\"fps\": n, \"quality\": q}, got " + show(*mp4));
      }
    }
    r.number("checkpoint_every", &o.output.checkpoint_every, closed(0.0, 1e6),
             "the checkpoint cadence (0: only at the end)");
    r.number("vtk_every", &o.output.vtk_every, closed(0.0, 1e6), "the ParaView output cadence (0: none)");
    r.finish();
  }
  {
    Reader r = root.object("render");
    render::RenderOptions& ro = o.render;
    r.integer("width", &ro.width, 16, 7680, "the frame width in pixels");
    r.integer("height", &ro.height, 16, 4320, "the frame height in pixels");
    if (ro.width % 2) r.error("width", "value " + std::to_string(ro.width) + " is odd: movies need even sizes");
    if (ro.height % 2) r.error("height", "value " + std::to_string(ro.height) + " is odd: movies need even sizes");
    const int view = r.choice("view", {"oblique", "xy", "xz", "yz"});
    if (view >= 0) ro.camera.view = static_cast<render::View>(view);
    r.boolean("orthographic", &ro.camera.orthographic);
    const int field = r.choice("field", {"max-tension", "min-tension", "mean-tension", "plain"});
    if (field >= 0) ro.field = static_cast<render::ColorField>(field);
    const int cmap = r.choice("colormap", {"viridis", "coolwarm"});
    if (cmap >= 0) ro.colormap = static_cast<render::ColorMap>(cmap);
    if (const json* range = r.get("range")) {
      if (range->is_string() && range->get<std::string>() == "auto") {
        ro.auto_range = true;
      } else if (range->is_array() && range->size() == 2 && (*range)[0].is_number() &&
                 (*range)[1].is_number() && (*range)[0].get<double>() < (*range)[1].get<double>()) {
        ro.auto_range = false;
        ro.range_min = (*range)[0].get<double>();
        ro.range_max = (*range)[1].get<double>();
      } else {
        r.error("range", "value " + show(*range) + " is not valid: range must be \"auto\" or "
                         "[min, max] with min < max");
      }
    }
    r.boolean("element_lines", &ro.element_lines);
    {
      Reader ov = r.object("overlay");
      ov.boolean("colorbar", &ro.overlay_colorbar);
      ov.boolean("text", &ro.overlay_text);
      ov.finish();
    }
    const int backend = r.choice("backend", {"auto", "egl", "osmesa"});
    if (backend >= 0) ro.backend = static_cast<render::Backend>(backend);
    r.integer("msaa", &ro.msaa, 0, 16, "the multisample count");
    r.boolean("preview", &ro.preview);
    r.finish();
  }
  {
    Reader r = root.object("numerics");
    r.boolean("smoothing", &o.numerics.smoothing);
    r.boolean("volume_correction", &o.numerics.volume_correction);
    r.boolean("symmetry", &o.numerics.symmetry);
    r.integer("threads", &o.numerics.threads, 0, 1024, "the OpenMP thread count (0: all)");
    r.number("quadrature_scale", &o.numerics.quadrature_scale, closed(1, 4),
             "the factor on every quadrature order");
    r.finish();
  }
  {
    Reader r = root.object("run");
    const int s = r.choice("state", {"running", "paused", "stopped"});
    if (s >= 0) o.run.state = static_cast<RunState>(s);
    r.boolean("checkpoint_now", &o.run.checkpoint_now);
    r.finish();
  }
  root.finish();
  if (!errors.empty()) throw ControlError(source, errors);

  // Warnings for legal but suspicious values.
  double ca_min = std::numeric_limits<double>::infinity();
  for (const auto& s : o.ca.segments)
    ca_min = std::min(ca_min, s.kind == CaSegment::Kind::Hold ? s.ca : s.to);
  const double dx = min_node_spacing(o.mesh);
  if (o.time.dt > ca_min * dx) {
    std::ostringstream s;
    s << "dt = " << o.time.dt << " exceeds the stability estimate Ca_min * dx_min = " << ca_min
      << " * " << dx << " = " << ca_min * dx << " (paper eq. 16): the run may become unstable";
    out.warnings.push_back({"time.dt", s.str()});
  }
  if (o.flow.type == capsule::FlowType::PlanarExtension && o.mesh.elements != 14 &&
      o.mesh.division == geometry::Division::Cube)
    out.warnings.push_back(
        {"mesh.division", std::string("\"cube\" with ") + std::to_string(o.mesh.elements) +
                              " elements: in planar extension the capsule's tips (+-x) lie in "
                              "the middle of a 90-degree cap element, whose resolution limits "
                              "volume conservation and stability (Skalak Ca=0.45, NB=8, t=1: "
                              "drift -1.8e-4 / -1.9e-4 on the NE=6 / NE=10 cube, -3.8e-6 / "
                              "-1.9e-6 with the default division \"diagonal\" / \"box\", "
                              "-3.9e-7 at NE=14)"});
  if (!o.numerics.smoothing)
    out.warnings.push_back({"numerics.smoothing", "false: without the membrane smoothing the "
                                                  "method is unstable (paper fig. 2a)"});
  if (o.output.frame_every > 0 && !o.output.png && !o.output.mp4.enabled)
    out.warnings.push_back({"output.frame_every", "frames are taken but neither png nor mp4 is on"});
  return out;
}

ParsedControl load_control_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ControlError(path, {{"", "cannot open the file"}});
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_control(ss.str(), path);
}

std::string to_json_text(const ControlOptions& o) {
  json j;
  if (!o.description.empty()) j["description"] = o.description;
  j["capsule"] = {{"law", o.law.kind == membrane::LawKind::Skalak
                              ? "skalak"
                              : (o.law.kind == membrane::LawKind::NeoHookean ? "neo-hookean"
                                                                             : "mooney-rivlin")},
                  {"C", o.law.c},
                  {"psi", o.law.psi},
                  {"viscosity_ratio", o.viscosity_ratio}};
  j["mesh"] = {{"elements", o.mesh.elements}, {"nb", o.mesh.nb},
               {"division", division_name(o.mesh.division)}};
  if (!o.start.from.empty())  // (an empty "from" is not valid input: omit the default)
    j["start"] = {{"from", o.start.from}, {"restore_volume", o.start.restore_volume}};
  j["flow"] = {{"type", o.flow.name()}};
  if (o.flow.type == capsule::FlowType::Custom) {
    json rows = json::array();
    for (int i = 0; i < 3; ++i)
      rows.push_back({o.flow.gradient(i, 0), o.flow.gradient(i, 1), o.flow.gradient(i, 2)});
    j["flow"]["gradient"] = rows;
  }
  j["time"] = {{"dt", o.time.dt}, {"t_end", o.time.t_end}};
  if (o.ca.constant && o.ca.segments.size() == 1) {
    j["ca"] = o.ca.segments[0].ca;
  } else {
    json list = json::array();
    for (const auto& s : o.ca.segments) {
      json hold = s.until_steady ? json("steady") : json(s.hold_time);
      switch (s.kind) {
        case CaSegment::Kind::Hold: list.push_back({{"ca", s.ca}, {"hold", hold}}); break;
        case CaSegment::Kind::Ramp: list.push_back({{"ramp", {{"to", s.to}, {"rate", s.rate}}}}); break;
        case CaSegment::Kind::Steps:
          list.push_back({{"steps", {{"to", s.to}, {"by", s.by}, {"hold", hold}}}});
          break;
      }
    }
    j["ca"] = list;
  }
  j["steady"] = {{"tolerance", o.steady.tolerance}, {"window", o.steady.window},
                 {"min_hold", o.steady.min_hold}, {"stop", o.steady.stop}};
  j["output"] = {{"dir", o.output.dir},
                 {"csv_every", o.output.csv_every},
                 {"frame_every", o.output.frame_every},
                 {"png", o.output.png},
                 {"mp4", o.output.mp4.enabled ? json{{"fps", o.output.mp4.fps},
                                                     {"quality", o.output.mp4.quality}}
                                              : json(false)},
                 {"checkpoint_every", o.output.checkpoint_every},
                 {"vtk_every", o.output.vtk_every}};
  j["numerics"] = {{"smoothing", o.numerics.smoothing},
                   {"volume_correction", o.numerics.volume_correction},
                   {"symmetry", o.numerics.symmetry},
                   {"threads", o.numerics.threads},
                   {"quadrature_scale", o.numerics.quadrature_scale}};
  {
    const render::RenderOptions& ro = o.render;
    static const char* views[] = {"oblique", "xy", "xz", "yz", "oblique"};
    static const char* fields[] = {"max-tension", "min-tension", "mean-tension", "plain"};
    static const char* cmaps[] = {"viridis", "coolwarm"};
    static const char* backends[] = {"auto", "egl", "osmesa"};
    j["render"] = {{"width", ro.width},
                   {"height", ro.height},
                   {"view", views[static_cast<int>(ro.camera.view)]},
                   {"orthographic", ro.camera.orthographic},
                   {"field", fields[static_cast<int>(ro.field)]},
                   {"colormap", cmaps[static_cast<int>(ro.colormap)]},
                   {"range", ro.auto_range ? json("auto") : json::array({ro.range_min, ro.range_max})},
                   {"element_lines", ro.element_lines},
                   {"overlay", {{"colorbar", ro.overlay_colorbar}, {"text", ro.overlay_text}}},
                   {"backend", backends[static_cast<int>(ro.backend)]},
                   {"msaa", ro.msaa},
                   {"preview", ro.preview}};
  }
  j["run"] = {{"state", to_string(o.run.state)}, {"checkpoint_now", o.run.checkpoint_now}};
  return j.dump(2) + "\n";
}

}  // namespace capflow::control
