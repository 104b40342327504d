#include "control/schema.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "capsule/viscosity_ratio.h"
#include "control/limits.h"
#include "control/schema_table.h"

namespace capflow::control::schema {

namespace {

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

std::string quoted_list(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::vector<std::string> q;
  for (const auto& s : v) q.push_back("\"" + s + "\"");
  return join(q, sep);
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1,
                         prev[j - 1] + (std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                                                std::tolower(static_cast<unsigned char>(b[j - 1]))
                                            ? 0
                                            : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
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
Range closed(double lo, double hi) {
  return {lo, hi, false, false};
}
Range open_closed(double lo, double hi) {
  return {lo, hi, true, false};
}

using Refs = ControlOptions&;
constexpr Mutability kFrozen = Mutability::Frozen;
constexpr Mutability kLive = Mutability::Live;

void add_error(ReadContext& c, const std::string& path, const std::string& message) {
  c.errors.push_back({path, message});
}

// Messages shared by the typed fields and the schedule's segment objects.
std::string number_issue(const json& v, const Range& r, const std::string& meaning, double* out) {
  if (!v.is_number())
    return "expected a number (" + meaning + " in " + r.text() + "), got " + show(v);
  const double d = v.get<double>();
  if (!std::isfinite(d) || !r.contains(d))
    return "value " + show(v) + " is out of range: " + meaning + " must be in " + r.text();
  *out = d;
  return "";
}

// An integer JSON value, unsigned ones above 2^40 clamped (every integer field is far smaller).
long long integer_value(const json& v) {
  if (v.is_number_unsigned())
    return static_cast<long long>(
        std::min<unsigned long long>(v.get<unsigned long long>(), 1ull << 40));
  return v.get<long long>();
}

template <class Ref>
Field number(const std::string& path, Ref ref, Range r, const std::string& meaning,
             const std::string& unit, Mutability m, const std::string& doc) {
  Field f;
  f.info = {path, "number", r.text(), "", unit, m, doc};
  f.read = [=](const json& v, ReadContext& c) {
    double d = 0;
    const std::string issue = number_issue(v, r, meaning, &d);
    if (!issue.empty()) return add_error(c, path, issue);
    ref(c.options) = d;
  };
  f.write = [=](const ControlOptions& o) -> std::optional<json> {
    return json(ref(const_cast<Refs>(o)));
  };
  f.copy = [=](ControlOptions& d, const ControlOptions& s) { ref(d) = ref(const_cast<Refs>(s)); };
  return f;
}

template <class Ref>
Field integer(const std::string& path, Ref ref, int lo, int hi, const std::string& meaning,
              const std::string& unit, Mutability m, const std::string& doc) {
  const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
  Field f;
  f.info = {path, "integer", range, "", unit, m, doc};
  f.read = [=](const json& v, ReadContext& c) {
    if (!v.is_number_integer())
      return add_error(c, path,
                       "expected an integer (" + meaning + ", " + range + "), got " + show(v));
    const long long i = integer_value(v);
    if (i < lo || i > hi)
      return add_error(
          c, path, "value " + show(v) + " is out of range: " + meaning + " must be in " + range);
    ref(c.options) = static_cast<int>(i);
  };
  f.write = [=](const ControlOptions& o) -> std::optional<json> {
    return json(ref(const_cast<Refs>(o)));
  };
  f.copy = [=](ControlOptions& d, const ControlOptions& s) { ref(d) = ref(const_cast<Refs>(s)); };
  return f;
}

template <class Ref>
Field integer_of(const std::string& path, Ref ref, const std::vector<int>& allowed,
                 const std::string& meaning, const std::string& unit, Mutability m,
                 const std::string& doc) {
  std::vector<std::string> a;
  for (int x : allowed) a.push_back(std::to_string(x));
  Field f;
  f.info = {path, "integer", join(a, " | "), "", unit, m, doc};
  f.read = [=](const json& v, ReadContext& c) {
    const bool ok =
        v.is_number_integer() && std::count(allowed.begin(), allowed.end(), integer_value(v)) > 0;
    if (!ok)
      return add_error(
          c, path,
          "value " + show(v) + " is not allowed: " + meaning + " must be one of " + join(a));
    ref(c.options) = static_cast<int>(integer_value(v));
  };
  f.write = [=](const ControlOptions& o) -> std::optional<json> {
    return json(ref(const_cast<Refs>(o)));
  };
  f.copy = [=](ControlOptions& d, const ControlOptions& s) { ref(d) = ref(const_cast<Refs>(s)); };
  return f;
}

template <class Ref>
Field boolean(const std::string& path, Ref ref, Mutability m, const std::string& doc) {
  Field f;
  f.info = {path, "boolean", "true | false", "", "", m, doc};
  f.read = [=](const json& v, ReadContext& c) {
    if (!v.is_boolean()) return add_error(c, path, "expected true or false, got " + show(v));
    ref(c.options) = v.get<bool>();
  };
  f.write = [=](const ControlOptions& o) -> std::optional<json> {
    return json(ref(const_cast<Refs>(o)));
  };
  f.copy = [=](ControlOptions& d, const ControlOptions& s) { ref(d) = ref(const_cast<Refs>(s)); };
  return f;
}

// A string; an empty one is the default and is omitted from the effective file when allowed.
template <class Ref>
Field text(const std::string& path, Ref ref, bool allow_empty, size_t max_bytes,
           const std::string& meaning, const std::string& valid, Mutability m,
           const std::string& doc) {
  Field f;
  f.info = {path, "string", valid, "", "", m, doc};
  f.read = [=](const json& v, ReadContext& c) {
    if (!v.is_string() || (!allow_empty && v.get<std::string>().empty()))
      return add_error(c, path,
                       std::string("expected a ") + (allow_empty ? "" : "non-empty ") + "string (" +
                           meaning + "), got " + show(v));
    const std::string s = v.get<std::string>();
    if (s.size() > max_bytes)
      return add_error(c, path,
                       "is " + std::to_string(s.size()) + " bytes long: " + meaning +
                           " may have at most " + std::to_string(max_bytes));
    ref(c.options) = s;
  };
  f.write = [=](const ControlOptions& o) -> std::optional<json> {
    const std::string& s = ref(const_cast<Refs>(o));
    if (s.empty()) return std::nullopt;  // "" is the default of the fields that may be absent
    return json(s);
  };
  f.copy = [=](ControlOptions& d, const ControlOptions& s) { ref(d) = ref(const_cast<Refs>(s)); };
  return f;
}

// One of `names`; get/set map the option to and from the index.
template <class Get, class Set>
Field choice(const std::string& path, Get get, Set set, const std::vector<std::string>& names,
             Mutability m, const std::string& doc) {
  Field f;
  f.info = {path, "choice", quoted_list(names, " | "), "", "", m, doc};
  f.read = [=](const json& v, ReadContext& c) {
    if (!v.is_string())
      return add_error(c, path, "expected one of " + quoted_list(names) + ", got " + show(v));
    const std::string s = v.get<std::string>();
    for (size_t i = 0; i < names.size(); ++i)
      if (s == names[i]) return set(c.options, static_cast<int>(i));
    const std::string sug = suggestion(s, names);
    add_error(c, path,
              "value " + show(v) + " is not one of " + quoted_list(names) +
                  (sug.empty() ? "" : " (did you mean \"" + sug + "\"?)"));
  };
  f.write = [=](const ControlOptions& o) -> std::optional<json> {
    const int i = get(o);
    return json(names.at(i >= 0 && i < static_cast<int>(names.size()) ? i : 0));
  };
  f.copy = [=](ControlOptions& d, const ControlOptions& s) { set(d, get(s)); };
  return f;
}

// ---------------------------------------------------------------------------------------------
// The Ca schedule: a number, or a list of segment objects (options.h).

// Reads one object of a schedule segment, remembering which keys were used; finish() reports
// the others with "did you mean".
class SegmentReader {
 public:
  SegmentReader(const json* j, std::string path, std::vector<ControlIssue>* errors)
      : j_(j), path_(std::move(path)), errors_(errors) {}
  std::string at(const std::string& key) const { return path_ + "." + key; }
  const json* get(const std::string& key) {
    known_.push_back(key);
    if (!j_ || !j_->is_object()) return nullptr;
    auto it = j_->find(key);
    return it == j_->end() ? nullptr : &*it;
  }
  bool present(const std::string& key) const { return j_ && j_->is_object() && j_->contains(key); }
  void error(const std::string& key, const std::string& msg) {
    errors_->push_back({key.empty() ? path_ : at(key), msg});
  }
  void number(const std::string& key, double* out, const Range& r, const std::string& meaning) {
    const json* v = get(key);
    if (!v) return;
    const std::string issue = number_issue(*v, r, meaning, out);
    if (!issue.empty()) error(key, issue);
  }
  SegmentReader object(const std::string& key) {
    const json* v = get(key);
    if (v && !v->is_object()) {
      error(key, "expected an object {...}, got " + show(*v));
      return SegmentReader(nullptr, at(key), errors_);
    }
    return SegmentReader(v, at(key), errors_);
  }
  void finish() {
    if (!j_ || !j_->is_object()) return;
    for (auto it = j_->begin(); it != j_->end(); ++it) {
      if (std::find(known_.begin(), known_.end(), it.key()) != known_.end()) continue;
      const std::string sug = suggestion(it.key(), known_);
      errors_->push_back(
          {at(it.key()), "unknown key" + (sug.empty() ? "" : " (did you mean \"" + sug + "\"?)") +
                             "; valid keys here: " + join(known_)});
    }
  }

 private:
  const json* j_;
  std::string path_;
  std::vector<ControlIssue>* errors_;
  std::vector<std::string> known_;
};

const Range kCaRange = open_closed(0.0, 100.0);

// "hold": "steady" or a duration.
void read_hold(SegmentReader& r, CaSegment* s) {
  const json* v = r.get("hold");
  if (!v) return;
  if (v->is_string() && v->get<std::string>() == "steady") {
    s->until_steady = true;
  } else if (v->is_number() && v->get<double>() > 0 && v->get<double>() <= 1e6) {
    s->until_steady = false;
    s->hold_time = v->get<double>();
  } else {
    r.error("hold",
            "value " + show(*v) + " is not valid: hold must be \"steady\" or a time in (0, 1e6]");
  }
}

// "ca": {"continuation": {"from", "to", "step", "after_fold"}} (capflow steady).
void read_continuation(const json& v, std::vector<ControlIssue>* errors, CaSchedule* out) {
  SegmentReader r(&v, "ca", errors);
  SegmentReader q = r.object("continuation");
  r.finish();
  Continuation c;
  q.number("from", &c.from, kCaRange, "the first Ca");
  q.number("to", &c.to, kCaRange, "the end of the Ca range");
  q.number("step", &c.step, open_closed(0.0, 10.0), "the largest change of Ca per state");
  double after = c.after_fold;
  q.number("after_fold", &after, closed(0.0, 1000.0), "the states beyond a fold");
  if (q.present("after_fold") && after != std::floor(after))
    q.error("after_fold", "value " + show(v["continuation"]["after_fold"]) +
                              " is not valid: after_fold must be a whole number in [0, 1000]");
  c.after_fold = static_cast<int>(after);
  if (const json* at = q.get("at")) {
    if (!at->is_array() || at->size() > 1000) {
      q.error("at", "expected a list of at most 1000 Ca values, got " + show(*at));
    } else {
      for (size_t i = 0; i < at->size(); ++i) {
        double a = 0;
        const std::string issue = number_issue((*at)[i], kCaRange, "Ca", &a);
        if (!issue.empty())
          q.error("at[" + std::to_string(i) + "]", issue);
        else
          c.at.push_back(a);
      }
    }
  }
  for (const char* key : {"from", "to", "step"})
    if (!q.present(key)) q.error("", std::string("missing \"") + key + "\"");
  q.finish();
  if (q.present("from") && q.present("to") && c.from == c.to)
    q.error("to",
            "value " + show(v["continuation"]["to"]) + " is not valid: the range needs to != from");
  out->continuation = c;
}

void read_schedule(const json& v, std::vector<ControlIssue>* errors, CaSchedule* out) {
  out->segments.clear();
  out->continuation.reset();
  if (v.is_object() && v.contains("continuation")) return read_continuation(v, errors, out);
  if (v.is_number()) {
    CaSegment s;
    const std::string issue = number_issue(v, kCaRange, "Ca", &s.ca);
    if (!issue.empty()) return errors->push_back({"ca", issue});
    out->constant = true;
    out->segments.push_back(s);
    return;
  }
  if (!v.is_array() || v.empty()) {
    errors->push_back({"ca",
                       "expected a number (constant Ca), a non-empty list of segments "
                       "({\"ca\": x, \"hold\": ...}, {\"ramp\": {...}}, {\"steps\": {...}}) or "
                       "{\"continuation\": {...}} (capflow steady), got " +
                           show(v)});
    return;
  }
  out->constant = false;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string path = "ca[" + std::to_string(i) + "]";
    if (!v[i].is_object()) {
      errors->push_back({path, "expected an object, got " + show(v[i])});
      continue;
    }
    SegmentReader r(&v[i], path, errors);
    CaSegment s;
    const int kinds = r.present("ca") + r.present("ramp") + r.present("steps");
    if (kinds != 1) {
      errors->push_back({path,
                         "a segment needs exactly one of \"ca\" (hold a level), \"ramp\" or "
                         "\"steps\", got " +
                             show(v[i])});
      continue;
    }
    if (r.present("ca")) {
      s.kind = CaSegment::Kind::Hold;
      r.number("ca", &s.ca, kCaRange, "Ca");
      read_hold(r, &s);
    } else if (r.present("ramp")) {
      s.kind = CaSegment::Kind::Ramp;
      SegmentReader q = r.object("ramp");
      q.number("to", &s.to, kCaRange, "the final Ca");
      q.number("rate", &s.rate, open_closed(0.0, 1e3), "|dCa/dt|");
      if (!q.present("to")) q.error("", "missing \"to\" (the final Ca)");
      if (!q.present("rate")) q.error("", "missing \"rate\" (|dCa/dt| > 0)");
      q.finish();
    } else {
      s.kind = CaSegment::Kind::Steps;
      SegmentReader q = r.object("steps");
      q.number("to", &s.to, kCaRange, "the final Ca");
      q.number("by", &s.by, open_closed(0.0, 100.0), "the increment");
      read_hold(q, &s);
      if (!q.present("to")) q.error("", "missing \"to\" (the final Ca)");
      if (!q.present("by")) q.error("", "missing \"by\" (the increment, > 0)");
      q.finish();
    }
    r.finish();
    out->segments.push_back(s);
  }
}

json schedule_json(const CaSchedule& ca) {
  if (ca.continuation)
    return {{"continuation",
             {{"from", ca.continuation->from},
              {"to", ca.continuation->to},
              {"step", ca.continuation->step},
              {"after_fold", ca.continuation->after_fold},
              {"at", ca.continuation->at}}}};
  if (ca.constant && ca.segments.size() == 1) return ca.segments[0].ca;
  json list = json::array();
  for (const auto& s : ca.segments) {
    const json hold = s.until_steady ? json("steady") : json(s.hold_time);
    switch (s.kind) {
      case CaSegment::Kind::Hold:
        list.push_back({{"ca", s.ca}, {"hold", hold}});
        break;
      case CaSegment::Kind::Ramp:
        list.push_back({{"ramp", {{"to", s.to}, {"rate", s.rate}}}});
        break;
      case CaSegment::Kind::Steps:
        list.push_back({{"steps", {{"to", s.to}, {"by", s.by}, {"hold", hold}}}});
        break;
    }
  }
  return list;
}

// flow.gradient: 3 rows of 3 finite numbers, |G_ij| <= 100, not all zero, trace within 1e-9 of
// the largest entry (then removed from the diagonal: Flow::custom needs it exact).
void read_gradient(const json& v, ReadContext& c) {
  auto error = [&c](const std::string& m) { add_error(c, "flow.gradient", m); };
  Eigen::Matrix3d g;
  const bool shape =
      v.is_array() && v.size() == 3 && std::all_of(v.begin(), v.end(), [](const json& row) {
        return row.is_array() && row.size() == 3 &&
               std::all_of(row.begin(), row.end(), [](const json& x) { return x.is_number(); });
      });
  if (!shape)
    return error("expected 3 rows of 3 numbers (the velocity gradient G, u = G x), got " + show(v));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      g(i, j) = v[i][j].get<double>();
      if (!std::isfinite(g(i, j)) || std::abs(g(i, j)) > 100)
        return error("entry [" + std::to_string(i) + "][" + std::to_string(j) + "] = " +
                     show(v[i][j]) + " is out of range: every entry must be in [-100, 100]");
    }
  const double big = g.cwiseAbs().maxCoeff();
  if (big == 0)
    return error("is zero: give a nonzero gradient (its scale sets the time unit and Ca)");
  if (std::abs(g.trace()) > 1e-9 * big) {
    std::ostringstream m;
    m << "has trace " << g.trace() << ": the flow must be incompressible, G00 + G11 + G22 = 0";
    return error(m.str());
  }
  g.diagonal().array() -= g.trace() / 3;
  c.options.flow = capsule::Flow::custom(g);
}

Field custom(FieldInfo info, std::function<void(const json&, ReadContext&)> read,
             std::function<std::optional<json>(const ControlOptions&)> write,
             std::function<void(ControlOptions&, const ControlOptions&)> copy = nullptr) {
  return Field{std::move(info), std::move(read), std::move(write), std::move(copy)};
}

std::vector<Field> build_fields() {
  using O = ControlOptions;
  std::vector<Field> t;
  t.push_back(text(
      "description", [](O& o) -> std::string& { return o.description; }, true, kMaxDescriptionBytes,
      "a free-text description of the run", "text of at most 65536 bytes", kFrozen,
      "free text, logged with the run"));
  t.back().info.default_value = "\"\"";
  // capsule
  t.push_back(choice(
      "capsule.law", [](const O& o) { return static_cast<int>(o.law.kind); },
      [](O& o, int i) { o.law.kind = static_cast<membrane::LawKind>(i); },
      {"skalak", "neo-hookean", "mooney-rivlin"}, kFrozen, "membrane law (paper eqs. 11-13)"));
  t.push_back(number(
      "capsule.C", [](O& o) -> double& { return o.law.c; }, open_closed(-0.5, 1e4),
      "the Skalak area-dilatation parameter C", "", kFrozen,
      "Skalak area-dilatation parameter (area modulus (1+2C) Gs)"));
  t.push_back(number(
      "capsule.psi", [](O& o) -> double& { return o.law.psi; }, closed(0, 1),
      "the Mooney-Rivlin parameter psi", "", kFrozen, "Mooney-Rivlin parameter (1 = neo-Hookean)"));
  t.push_back(custom(
      {"capsule.shape", "string or object",
       "\"sphere\" | \"biconcave\" | {\"biconcave\": {\"axis\": A}} | {\"spheroid\": "
       "{\"aspect\": r in [0.1, 10], \"axis\": A}}, A one of \"x\", \"y\", \"z\" (default z)",
       "\"sphere\"", "a", kFrozen,
       "the stress-free reference shape, also the initial shape, scaled to the equal-volume "
       "radius a: a sphere, the Evans-Fung red blood cell, or a spheroid with polar/equatorial "
       "aspect r (> 1 prolate), about their symmetry axis"},
      [](const json& v, ReadContext& c) {
        geometry::ReferenceShape& s = c.options.shape;
        s = geometry::ReferenceShape{};
        if (v.is_string() && v.get<std::string>() == "sphere") return;
        if (v.is_string() && v.get<std::string>() == "biconcave") {
          s.kind = geometry::ReferenceShape::Kind::Biconcave;
          return;
        }
        auto sp = v.is_object() && v.size() == 1 ? v.find("spheroid") : v.end();
        bool spheroid = true;
        if (v.is_object() && v.size() == 1 && sp == v.end()) {
          sp = v.find("biconcave");
          spheroid = false;
        }
        if (sp == v.end() || !sp->is_object())
          return add_error(c, "capsule.shape",
                           "value " + show(v) + " is not valid: give \"sphere\", \"biconcave\", "
                           "{\"biconcave\": {\"axis\": \"x\"}} or {\"spheroid\": {\"aspect\": r, "
                           "\"axis\": \"z\"}}");
        const std::string at = std::string("capsule.shape.") + (spheroid ? "spheroid." : "biconcave.");
        s.kind = spheroid ? geometry::ReferenceShape::Kind::Spheroid
                          : geometry::ReferenceShape::Kind::Biconcave;
        for (auto it = sp->begin(); it != sp->end(); ++it) {
          if (it.key() == "aspect" && spheroid) {
            if (!it->is_number() || !(it->get<double>() >= 0.1 && it->get<double>() <= 10))
              return add_error(c, at + "aspect",
                               "value " + show(*it) + " is out of range: the aspect must be a "
                               "number in [0.1, 10]");
            s.aspect = it->get<double>();
          } else if (it.key() == "axis") {
            const std::string a = it->is_string() ? it->get<std::string>() : "";
            if (a != "x" && a != "y" && a != "z")
              return add_error(c, at + "axis",
                               "value " + show(*it) + " is not valid: \"x\", \"y\" or \"z\"");
            s.axis = a == "x" ? 0 : a == "y" ? 1 : 2;
          } else {
            return add_error(c, at + it.key(),
                             spheroid ? "is not a key of a spheroid (aspect, axis)"
                                      : "is not a key of the biconcave shape (axis)");
          }
        }
        if (spheroid && sp->find("aspect") == sp->end())
          add_error(c, "capsule.shape.spheroid.aspect", "is required (a number in [0.1, 10])");
      },
      [](const O& o) -> std::optional<json> {
        const geometry::ReferenceShape& s = o.shape;
        const std::string axis(1, "xyz"[s.axis]);
        if (s.kind == geometry::ReferenceShape::Kind::Spheroid)
          return json{{"spheroid", {{"aspect", s.aspect}, {"axis", axis}}}};
        if (s.kind == geometry::ReferenceShape::Kind::Biconcave && s.axis != 2)
          return json{{"biconcave", {{"axis", axis}}}};
        return json(geometry::shape_name(s.kind));
      },
      [](O& dst, const O& src) { dst.shape = src.shape; }));
  t.push_back(number(
      "capsule.bending.modulus", [](O& o) -> double& { return o.bending.modulus; }, closed(0, 1),
      "the bending modulus Eb", "Gs a^2", kFrozen,
      "Eb = kappa_b / (Gs a^2), the bending stiffness (0: none; red blood cells ~5e-3)"));
  t.push_back(choice(
      "capsule.bending.model", [](const O& o) { return static_cast<int>(o.bending.model); },
      [](O& o, int i) { o.bending.model = static_cast<membrane::BendingModel>(i); },
      {"helfrich", "reference"}, kFrozen,
      "helfrich: W = (kappa_b/2) INT (2H - c0)^2 dA with a uniform c0; reference: c0 = 2H of the "
      "reference shape at each material point (shape memory)"));
  t.push_back(number(
      "capsule.bending.c0", [](O& o) -> double& { return o.bending.c0; }, closed(-10, 10),
      "the spontaneous curvature c0", "1/a", kFrozen,
      "spontaneous curvature of the helfrich model (2/a: the sphere's own)"));
  t.push_back(number(
      "capsule.viscosity_ratio", [](O& o) -> double& { return o.viscosity_ratio; },
      open_closed(0, capsule::kMaxViscosityRatio), "the viscosity ratio", "", kFrozen,
      "lambda, inner / outer viscosity; other than 1, each velocity evaluation solves the "
      "double-layer equation by GMRES"));
  // mesh
  t.push_back(integer_of(
      "mesh.elements", [](O& o) -> int& { return o.mesh.elements; }, {6, 10, 14},
      "the element division", "", kFrozen, "elements of the sphere (paper fig. 1)"));
  t.push_back(integer(
      "mesh.nb", [](O& o) -> int& { return o.mesh.nb; }, 4, 24, "nodes per element direction", "",
      kFrozen, "Gauss-Lobatto nodes per element direction"));
  {
    Field f = choice(
        "mesh.division", [](const O& o) { return static_cast<int>(o.mesh.division); },
        [](O& o, int i) { o.mesh.division = static_cast<geometry::Division>(i); },
        {"cube", "box", "diagonal"}, kFrozen,
        "cube: faces split in equal angles; box: the paper's parallelepiped; diagonal (NE=6 "
        "only): the cube turned 45 degrees about z (docs/validation.md)");
    f.info.default_value =
        "planar extension: \"diagonal\" (NE=6), \"box\" (NE=10), \"cube\" (NE=14); otherwise "
        "\"cube\"";
    t.push_back(f);
  }
  // start
  {
    Field f = text(
        "start.from", [](O& o) -> std::string& { return o.start.from; }, false, 4096,
        "a run directory or checkpoint file to start from", "a run directory or a .ckpt file",
        kFrozen,
        "start from that run's newest checkpoint, resampled onto this mesh; time "
        "goes on from its t");
    f.info.default_value = "none: the unstressed sphere at t = 0";
    t.push_back(f);
  }
  {
    Field f = boolean(
        "start.restore_volume", [](O& o) -> bool& { return o.start.restore_volume; }, kFrozen,
        "scale the resampled shape to the sphere's volume");
    // Without start.from it means nothing: left out at its default, but written when set (so
    // that a live edit of it is seen, and refused like any frozen key).
    const auto write = f.write;
    f.write = [write](const O& o) {
      return o.start.from.empty() && o.start.restore_volume ? std::nullopt : write(o);
    };
    f.info.default_value = "true";
    t.push_back(f);
  }
  // flow
  t.push_back(choice(
      "flow.type", [](const O& o) { return static_cast<int>(o.flow.type); },
      [](O& o, int i) {
        if (i == 0) o.flow = capsule::Flow::planar_extension();
        if (i == 1) o.flow = capsule::Flow::simple_shear();
        if (i == 2) o.flow.type = capsule::FlowType::Custom;  // flow.gradient sets G
      },
      {"planar-extension", "simple-shear", "custom"}, kFrozen,
      "u = (x, -y, 0), (z, 0, 0), or u = G x with flow.gradient"));
  t.push_back(custom(
      {"flow.gradient", "3 x 3 numbers",
       "rows of numbers in [-100, 100], not all 0, trace 0 (below 1e-9 of the largest: removed)",
       "none: required with \"custom\", refused otherwise", "G", kFrozen,
       "velocity gradient G_ij = du_i/dx_j; its scale sets the time unit and Ca"},
      read_gradient, [](const O& o) -> std::optional<json> {
        if (o.flow.type != capsule::FlowType::Custom) return std::nullopt;
        json rows = json::array();
        for (int i = 0; i < 3; ++i)
          rows.push_back({o.flow.gradient(i, 0), o.flow.gradient(i, 1), o.flow.gradient(i, 2)});
        return rows;
      }));
  // time
  t.push_back(custom(
      {"time.dt", "number or \"auto\"",
       "\"auto\", or a number in " + closed(kMinTimeStep, 0.1).text(), "\"auto\"", "1/G", kLive,
       "\"auto\": adaptive steps that keep the local error below time.tolerance and find the "
       "stability limit; a number: the fixed RK4 step (stable for dt < O(Ca dx_min))"},
      [](const json& v, ReadContext& c) {
        if (v.is_string() && v.get<std::string>() == "auto") {
          c.options.time.adaptive = true;
          return;
        }
        double d = 0;
        const std::string issue =
            number_issue(v, closed(kMinTimeStep, 0.1), "the time step dt (or \"auto\")", &d);
        if (!issue.empty()) return add_error(c, "time.dt", issue);
        c.options.time.adaptive = false;
        c.options.time.dt = d;
      },
      [](const O& o) -> std::optional<json> {
        return o.time.adaptive ? json("auto") : json(o.time.dt);
      },
      [](O& d, const O& s) {
        d.time.adaptive = s.time.adaptive;
        d.time.dt = s.time.dt;
      }));
  t.push_back(number(
      "time.tolerance", [](O& o) -> double& { return o.time.tolerance; }, closed(1e-10, 1e-2),
      "the local error tolerance", "a", kLive,
      "adaptive steps (time.dt \"auto\"): relative and absolute local error per step of the "
      "node positions"));
  t.push_back(number(
      "time.t_end", [](O& o) -> double& { return o.time.t_end; }, open_closed(0, 1e6),
      "the end time t_end", "1/G", kLive,
      "simulated end time (fixed dt: at least dt, at most 1e7 steps)"));
  // ca
  t.push_back(custom(
      {"ca", "number, list or object", "(0, 100], a list of segments or a continuation (below)",
       "required", "", kLive, "capillary number mu G a / Gs, or a schedule of segments"},
      [](const json& v, ReadContext& c) { read_schedule(v, &c.errors, &c.options.ca); },
      [](const O& o) -> std::optional<json> { return schedule_json(o.ca); },
      [](O& d, const O& s) { d.ca = s.ca; }));
  // steady
  t.push_back(number(
      "steady.tolerance", [](O& o) -> double& { return o.steady.tolerance; }, open_closed(0, 1),
      "the steady-state rate tolerance", "a G", kLive,
      "steady when max |dL/dt|, |dS/dt|, |dW/dt| over the window is below this"));
  t.push_back(number(
      "steady.window", [](O& o) -> double& { return o.steady.window; }, open_closed(0, 100),
      "the steady-state window", "1/G", kLive, "time over which the rates are measured"));
  t.push_back(number(
      "steady.min_hold", [](O& o) -> double& { return o.steady.min_hold; }, closed(0, 1e4),
      "the minimum hold time", "1/G", kLive,
      "minimum time at a level before a steady state counts"));
  t.push_back(boolean(
      "steady.stop", [](O& o) -> bool& { return o.steady.stop; }, kLive,
      "end the run at the steady state of the final level"));
  t.push_back(number(
      "steady.solve_tolerance", [](O& o) -> double& { return o.steady.solve_tolerance; },
      closed(1e-12, 1e-3), "capflow steady's residual tolerance", "a G", kLive,
      "capflow steady: largest node velocity of the step-map residual at a steady state"));
  // output
  t.push_back(text(
      "output.dir", [](O& o) -> std::string& { return o.output.dir; }, false, 4096,
      "the run directory", "a path", kFrozen, "run directory (created; -o overrides it)"));
  t.push_back(number(
      "output.csv_every", [](O& o) -> double& { return o.output.csv_every; }, open_closed(0, 1e6),
      "the CSV cadence", "1/G", kLive, "timeseries.csv cadence"));
  t.push_back(number(
      "output.frame_every", [](O& o) -> double& { return o.output.frame_every; }, closed(0, 1e6),
      "the frame cadence (0: none)", "1/G", kLive, "movie/PNG frame cadence (0: no frames)"));
  t.push_back(boolean(
      "output.png", [](O& o) -> bool& { return o.output.png; }, kFrozen,
      "write frames as frames/frame_NNNNNN.png"));
  t.push_back(integer(
      "output.mp4.fps", [](O& o) -> int& { return o.output.mp4.fps; }, 1, 240, "frames per second",
      "1/s", kFrozen, "movie frame rate"));
  t.push_back(integer(
      "output.mp4.quality", [](O& o) -> int& { return o.output.mp4.quality; }, 0, 51,
      "the x264 CRF (0 best, 51 worst)", "", kFrozen,
      "x264 constant rate factor (lower is better)"));
  t.push_back(number(
      "output.checkpoint_every", [](O& o) -> double& { return o.output.checkpoint_every; },
      closed(0, 1e6), "the checkpoint cadence (0: only at the start and the end)", "1/G", kLive,
      "checkpoint cadence (0: at the start, the end and on request only)"));
  t.push_back(number(
      "output.vtk_every", [](O& o) -> double& { return o.output.vtk_every; }, closed(0, 1e6),
      "the ParaView output cadence (0: none)", "1/G", kLive, "ParaView surface cadence (0: none)"));
  t.push_back(integer(
      "output.vtk_points", [](O& o) -> int& { return o.output.vtk_points; }, 0, 64,
      "the ParaView surface's points per element edge (0: the nodes, else 2 to 64)", "", kFrozen,
      "ParaView surface points per element edge: the interpolant at n Gauss-Lobatto points "
      "(0: the nodes)"));
  // render
  t.push_back(integer(
      "render.width", [](O& o) -> int& { return o.render.width; }, 16, render::kMaxWidth,
      "the frame width in pixels", "px", kFrozen, "frame width (even)"));
  t.push_back(integer(
      "render.height", [](O& o) -> int& { return o.render.height; }, 16, render::kMaxHeight,
      "the frame height in pixels", "px", kFrozen, "frame height (even)"));
  t.push_back(choice(
      "render.view",
      [](const O& o) {
        const int v = static_cast<int>(o.render.camera.view);
        return v <= 3 ? v : 0;
      },
      [](O& o, int i) { o.render.camera.view = static_cast<render::View>(i); },
      {"oblique", "xy", "xz", "yz"}, kFrozen, "camera direction"));
  t.push_back(boolean(
      "render.orthographic", [](O& o) -> bool& { return o.render.camera.orthographic; }, kFrozen,
      "orthographic instead of perspective projection"));
  t.push_back(choice(
      "render.field", [](const O& o) { return static_cast<int>(o.render.field); },
      [](O& o, int i) { o.render.field = static_cast<render::ColorField>(i); },
      {"max-tension", "min-tension", "mean-tension", "plain"}, kFrozen, "colour field"));
  t.push_back(choice(
      "render.colormap", [](const O& o) { return static_cast<int>(o.render.colormap); },
      [](O& o, int i) { o.render.colormap = static_cast<render::ColorMap>(i); },
      {"viridis", "coolwarm"}, kFrozen, "colour map (coolwarm: symmetric range)"));
  t.push_back(custom(
      {"render.range", "\"auto\", \"frame\" or [min, max]",
       "\"auto\" | \"frame\" | [min, max] with min < max, both within +-1e12, max - min at "
       "least 1e-12 and 1e-9 of the larger bound",
       "\"auto\"", "Gs", kFrozen,
       "colour range: \"auto\" holds every value drawn so far and only grows (one colour, one "
       "tension over a movie), \"frame\" each frame's own, [min, max] fixed (beyond it marked "
       "on the bar)"},
      [](const json& v, ReadContext& c) {
        render::RenderOptions& ro = c.options.render;
        if (v.is_string() && v.get<std::string>() == "auto") {
          ro.range_mode = render::RangeMode::Grow;
        } else if (v.is_string() && v.get<std::string>() == "frame") {
          ro.range_mode = render::RangeMode::Frame;
        } else if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()) {
          const std::string why =
              render::fixed_range_problem(v[0].get<double>(), v[1].get<double>());
          if (!why.empty()) {
            add_error(c, "render.range", "value " + show(v) + " is not valid: " + why);
            return;
          }
          ro.range_mode = render::RangeMode::Fixed;
          ro.range_min = v[0].get<double>();
          ro.range_max = v[1].get<double>();
        } else {
          add_error(c, "render.range",
                    "value " + show(v) +
                        " is not valid: range must be \"auto\", \"frame\" or "
                        "[min, max] with min < max");
        }
      },
      [](const O& o) -> std::optional<json> {
        const render::RenderOptions& ro = o.render;
        if (ro.range_mode == render::RangeMode::Fixed)
          return json::array({ro.range_min, ro.range_max});
        return json(ro.range_mode == render::RangeMode::Frame ? "frame" : "auto");
      }));
  t.push_back(boolean(
      "render.element_lines", [](O& o) -> bool& { return o.render.element_lines; }, kFrozen,
      "draw element edges"));
  t.push_back(boolean(
      "render.overlay.colorbar", [](O& o) -> bool& { return o.render.overlay_colorbar; }, kFrozen,
      "colour bar"));
  t.push_back(boolean(
      "render.overlay.text", [](O& o) -> bool& { return o.render.overlay_text; }, kFrozen,
      "t, Ca, D and the law in the corner"));
  t.push_back(choice(
      "render.backend", [](const O& o) { return static_cast<int>(o.render.backend); },
      [](O& o, int i) { o.render.backend = static_cast<render::Backend>(i); },
      {"auto", "egl", "osmesa"}, kFrozen, "headless GL (auto: EGL, then OSMesa)"));
  t.push_back(choice(
      "render.antialias", [](const O& o) { return static_cast<int>(o.render.antialias); },
      [](O& o, int i) { o.render.antialias = static_cast<render::Antialias>(i); },
      {"auto", "msaa", "lines", "off"}, kFrozen,
      "edge anti-aliasing: msaa (render.msaa samples), lines (smooth lines along the outline and "
      "the element edges; a third of the CPU on a software rasteriser); auto: lines on "
      "llvmpipe / OSMesa, msaa on a GPU"));
  t.push_back(integer(
      "render.msaa", [](O& o) -> int& { return o.render.msaa; }, 0, 16, "the multisample count", "",
      kFrozen,
      "samples when multisampling (the largest count the GL supports up to this, with a warning)"));
  t.push_back(boolean(
      "render.preview", [](O& o) -> bool& { return o.render.preview; }, kFrozen,
      "keep preview.png current (never blocks the solver)"));
  // numerics
  t.push_back(boolean(
      "numerics.smoothing", [](O& o) -> bool& { return o.numerics.smoothing; }, kFrozen,
      "the paper's first-order membrane smoothing (off: unstable)"));
  t.push_back(boolean(
      "numerics.volume_correction", [](O& o) -> bool& { return o.numerics.volume_correction; },
      kLive, "rescale to the initial volume after each step (paper eq. 23)"));
  t.push_back(boolean(
      "numerics.symmetry", [](O& o) -> bool& { return o.numerics.symmetry; }, kFrozen,
      "evaluate velocities on the nodes the flow's symmetry leaves distinct"));
  t.push_back(integer(
      "numerics.threads", [](O& o) -> int& { return o.numerics.threads; }, 0, 1024,
      "the OpenMP thread count (0: all)", "", kLive, "OpenMP threads (0: all cores)"));
  t.push_back(number(
      "numerics.quadrature_scale", [](O& o) -> double& { return o.numerics.quadrature_scale; },
      closed(1, 4), "the factor on every quadrature order", "", kFrozen,
      "every boundary-integral quadrature order times this (accuracy checks)"));
  // run
  t.push_back(choice(
      "run.state", [](const O& o) { return static_cast<int>(o.run.state); },
      [](O& o, int i) { o.run.state = static_cast<RunState>(i); }, {"running", "paused", "stopped"},
      kLive, "paused holds the run; stopped ends it with a checkpoint"));
  t.push_back(boolean(
      "run.checkpoint_now", [](O& o) -> bool& { return o.run.checkpoint_now; }, kLive,
      "write a checkpoint when this becomes true"));

  const ControlOptions defaults;
  for (Field& f : t)
    if (f.info.default_value.empty())
      if (const auto v = f.write(defaults)) f.info.default_value = v->dump();
  return t;
}

std::vector<Group> build_groups() {
  std::vector<Group> g = {
      {"capsule", "the membrane", nullptr, nullptr},
      {"capsule.bending", "bending stiffness (method.md sec. 10)", nullptr, nullptr},
      {"mesh", "the spectral element mesh", nullptr, nullptr},
      {"start", "the initial shape", nullptr, nullptr},
      {"flow", "the imposed flow", nullptr, nullptr},
      {"time", "time stepping", nullptr, nullptr},
      {"steady", "steady-state detection", nullptr, nullptr},
      {"output", "what the run writes", nullptr, nullptr},
      {"output.mp4", "the movie: false, true (defaults) or an object",
       [](ControlOptions& o, bool on) { o.output.mp4.enabled = on; },
       [](const ControlOptions& o) { return o.output.mp4.enabled; }},
      {"render", "how frames look", nullptr, nullptr},
      {"render.overlay", "text and colour bar drawn over frames", nullptr, nullptr},
      {"numerics", "solver options", nullptr, nullptr},
      {"run", "steering", nullptr, nullptr},
  };
  return g;
}

std::string parent_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? "" : path.substr(0, dot);
}
std::string leaf_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

}  // namespace

// Which commands take an edit of each live key: capflow run every one; capflow steady those its
// solver uses.
std::vector<Field> with_live_commands(std::vector<Field> t) {
  static const char* const kSteadyLive[] = {"ca", "steady.solve_tolerance", "time.tolerance",
                                            "run.state"};
  for (Field& f : t) {
    if (f.info.mutability != kLive) continue;
    f.info.live_in = bit(Command::Run);
    for (const char* k : kSteadyLive)
      if (f.info.path == k) f.info.live_in |= bit(Command::Steady);
  }
  return t;
}

const std::vector<Field>& fields() {
  static const std::vector<Field> t = with_live_commands(build_fields());
  return t;
}

const std::vector<Group>& groups() {
  static const std::vector<Group> g = build_groups();
  return g;
}

const Field* find_field(const std::string& path) {
  for (const Field& f : fields())
    if (f.info.path == path) return &f;
  return nullptr;
}

const Group* find_group(const std::string& path) {
  for (const Group& g : groups())
    if (g.path == path) return &g;
  return nullptr;
}

std::vector<std::string> names_under(const std::string& group) {
  std::vector<std::string> out;
  auto add = [&](const std::string& path) {
    if (parent_of(path) != group) return;
    const std::string leaf = leaf_of(path);
    if (std::find(out.begin(), out.end(), leaf) == out.end()) out.push_back(leaf);
  };
  for (const Field& f : fields()) {
    // a field inside a sub-group names the sub-group here (e.g. "output.mp4.fps" -> "mp4")
    std::string p = f.info.path;
    while (!p.empty() && parent_of(p) != group && p.size() > group.size()) p = parent_of(p);
    add(p);
  }
  for (const Group& g : groups()) add(g.path);
  return out;
}

std::string show(const json& v) {
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string suggestion(const std::string& word, const std::vector<std::string>& options) {
  if (word.size() > 64) return "";
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

}  // namespace capflow::control::schema

namespace capflow::control {

const char* command_name(Command c) {
  return c == Command::Steady ? "steady" : "run";
}

const std::vector<FieldInfo>& control_fields() {
  static const std::vector<FieldInfo> info = [] {
    std::vector<FieldInfo> v;
    for (const schema::Field& f : schema::fields()) v.push_back(f.info);
    return v;
  }();
  return info;
}

namespace {
// "frozen", "live (run)", "live (run, steady)".
std::string live_text(const FieldInfo& f) {
  if (f.mutability != Mutability::Live) return "frozen";
  std::string s;
  for (Command c : {Command::Run, Command::Steady})
    if (f.live_for(c)) s += (s.empty() ? "" : ", ") + std::string(command_name(c));
  return "live (" + s + ")";
}
}  // namespace

std::string control_reference_markdown() {
  std::ostringstream m;
  auto cell = [](std::string s) {
    for (size_t p = 0; (p = s.find('|', p)) != std::string::npos; p += 2) s.replace(p, 1, "\\|");
    return s;
  };
  m << "# Control file reference\n\n"
    << "<!-- Generated by `capflow reference` from src/control/schema.cpp; do not edit. "
       "A test fails when this file is stale. -->\n\n"
    << "A control file is a JSON object. Every key except `ca` is optional; a key that is not "
       "listed here is refused (with \"did you mean\"), as is a key given twice. Units: lengths "
       "in the capsule radius a, time in 1/G (G the rate of the imposed flow), tensions in Gs, "
       "Ca = mu G a / Gs.\n\n"
    << "**Live** keys may be edited while a run goes on (the edit applies at the next step "
       "boundary); the edit column names the commands that take it (`capflow steady` uses "
       "fewer keys than `capflow run`). A live edit of a **frozen** key, or of a key the command "
       "does not take, is refused with a message while the rest of the edit applies. An edit "
       "that does not parse or validate is refused as a whole, except for `run.state` and "
       "`run.checkpoint_now`, which are honoured alone (a stop saved in a file that is refused "
       "otherwise still stops the run).\n\n"
    << "| key | type | valid | default | unit | edit | meaning |\n"
    << "|---|---|---|---|---|---|---|\n";
  for (const FieldInfo& f : control_fields())
    m << "| `" << f.path << "` | " << f.type << " | " << cell(f.valid) << " | "
      << cell(f.default_value) << " | " << f.unit << " | "
      << live_text(f) << " | " << cell(f.doc) << " |\n";
  m << "\n`output.mp4` may also be `false` (no movie) or `true` (the defaults).\n\n"
    << "## Ca schedules\n\n"
    << "`\"ca\": 0.45` holds Ca = 0.45 for the whole run (a steady state is still detected and "
       "written to steady.csv). A list runs its segments in order:\n\n"
    << "| segment | meaning |\n|---|---|\n"
    << "| `{\"ca\": x, \"hold\": \"steady\"}` | hold Ca = x until steady state (`hold` "
       "defaults to \"steady\") |\n"
    << "| `{\"ca\": x, \"hold\": T}` | hold Ca = x for the time T, (0, 1e6] |\n"
    << "| `{\"ramp\": {\"to\": x, \"rate\": r}}` | change Ca linearly at \\|dCa/dt\\| = r, "
       "(0, 1000], to x |\n"
    << "| `{\"steps\": {\"to\": x, \"by\": b, \"hold\": ...}}` | jump by b, (0, 100], towards x "
       "and hold each level (until steady, or for a time) |\n\n"
    << "A ramp or steps start from the Ca the previous segment ended at; a schedule that begins "
       "with one starts from the current Ca (after `start.from`, the source run's Ca; from rest, "
       "steps start at 0 and a ramp is refused: it would pass through Ca = 0). After the last "
       "segment its final level is held until `t_end`.\n\n"
    << "`capflow steady` solves at the levels of a number, of holds and of steps (a ramp has "
       "none), or follows a branch: `\"ca\": {\"continuation\": {\"from\": a, \"to\": b, "
       "\"step\": s, \"after_fold\": n}}` (pseudo-arclength continuation from Ca = a towards b; "
       "s, (0, 10], is the first and the largest change of Ca per state, the steps adapt down "
       "to s/64; a fold, a largest or smallest Ca of the branch, is located and reported, and "
       "n, [0, 1000], default 3, more states follow on the branch beyond it; `\"at\": [...]` lists "
       "Ca values to land on exactly where the branch passes them). `capflow run` refuses a "
       "continuation.\n\n"
    << "## Limits\n\n"
    << "| what | limit |\n|---|---|\n"
    << "| control file | a regular file (a symlink to one is followed), at most "
    << (kMaxControlBytes >> 20) << " MiB |\n"
    << "| nesting of objects and arrays | " << kMaxControlDepth << " levels |\n"
    << "| numbers | within the range of a double (1e400 is refused) |\n"
    << "| `description` | " << kMaxDescriptionBytes << " bytes |\n"
    << "| `time.dt` | at least " << kMinTimeStep << "; \"auto\" steps never fall below it "
    << "(the run fails instead) |\n"
    << "| `time.t_end` | after the run's time; with a fixed `time.dt` at least `time.dt`, and "
    << "at most " << kMaxSteps << " steps (`t_end / dt`) |\n";
  return m.str();
}

std::string control_fuzz_dictionary() {
  std::set<std::string> words;
  for (const schema::Field& f : schema::fields()) {
    std::string p = f.info.path;
    for (size_t s = 0, e; s <= p.size(); s = e + 1) {
      e = p.find('.', s);
      if (e == std::string::npos) e = p.size();
      words.insert(p.substr(s, e - s));
    }
    if (f.info.type == "choice")
      for (size_t s = 0; (s = f.info.valid.find('"', s)) != std::string::npos;) {
        const size_t e = f.info.valid.find('"', s + 1);
        words.insert(f.info.valid.substr(s + 1, e - s - 1));
        s = e + 1;
      }
  }
  for (const char* w : {"hold", "steady", "ramp", "to", "rate", "steps", "by", "auto",
                        "continuation", "from", "step", "after_fold", "at"})
    words.insert(w);
  std::ostringstream d;
  d << "# libFuzzer dictionary of the control file: generated by `capflow reference "
       "--dictionary` from src/control/schema.cpp; do not edit.\n";
  for (const std::string& w : words) d << "\"" << w << "\"\n";
  return d.str();
}

}  // namespace capflow::control
