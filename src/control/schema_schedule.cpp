// capflow/control/schema_schedule: reads and writes the Ca schedule; reads flow.gradient.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "control/schema_builders.h"

namespace capflow::control::schema::detail {

namespace {

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

}  // namespace

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

}  // namespace capflow::control::schema::detail
