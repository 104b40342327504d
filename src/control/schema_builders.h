// capflow/control/schema_builders: the typed field makers and helpers schema*.cpp share (internal).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "control/schema_table.h"

namespace capflow::control::schema {

namespace detail {

inline std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

inline std::string quoted_list(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::vector<std::string> q;
  for (const auto& s : v) q.push_back("\"" + s + "\"");
  return join(q, sep);
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
inline Range closed(double lo, double hi) {
  return {lo, hi, false, false};
}
inline Range open_closed(double lo, double hi) {
  return {lo, hi, true, false};
}

using Refs = ControlOptions&;
inline constexpr Mutability kFrozen = Mutability::Frozen;
inline constexpr Mutability kLive = Mutability::Live;

inline void add_error(ReadContext& c, const std::string& path, const std::string& message) {
  c.errors.push_back({path, message});
}

// Messages shared by the typed fields and the schedule's segment objects.
inline std::string number_issue(const json& v, const Range& r, const std::string& meaning,
                                double* out) {
  if (!v.is_number())
    return "expected a number (" + meaning + " in " + r.text() + "), got " + show(v);
  const double d = v.get<double>();
  if (!std::isfinite(d) || !r.contains(d))
    return "value " + show(v) + " is out of range: " + meaning + " must be in " + r.text();
  *out = d;
  return "";
}

// An integer JSON value, unsigned ones above 2^40 clamped (every integer field is far smaller).
inline long long integer_value(const json& v) {
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

inline Field custom(FieldInfo info, std::function<void(const json&, ReadContext&)> read,
                    std::function<std::optional<json>(const ControlOptions&)> write,
                    std::function<void(ControlOptions&, const ControlOptions&)> copy = nullptr) {
  return Field{std::move(info), std::move(read), std::move(write), std::move(copy)};
}

// The Ca schedule and flow.gradient (schema_schedule.cpp).
void read_schedule(const json& v, std::vector<ControlIssue>* errors, CaSchedule* out);
json schedule_json(const CaSchedule& ca);
void read_gradient(const json& v, ReadContext& c);

// The field table and its groups (schema_fields.cpp).
std::vector<Field> build_fields();
std::vector<Group> build_groups();

}  // namespace detail

// The table with each live key's commands set (schema_fields.cpp).
std::vector<Field> with_live_commands(std::vector<Field> t);

}  // namespace capflow::control::schema
