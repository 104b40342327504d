#include "control/sweep.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "control/control_file.h"
#include "control/json_input.h"
#include "control/schema_table.h"

namespace capflow::control {

namespace fs = std::filesystem;
using nlohmann::json;
using schema::show;

std::string SweepCase::label() const {
  std::string s;
  for (const auto& [key, value] : values) s += (s.empty() ? "" : ", ") + key + " = " + value;
  return s;
}

namespace {

// The varied key's segments ("capsule.C" -> {"capsule", "C"}): non-empty names.
std::vector<std::string> segments(const std::string& key) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t dot = key.find('.', start);
    out.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return out;
}

bool valid_key(const std::string& key) {
  if (key.empty()) return false;
  for (const std::string& s : segments(key))
    if (s.empty()) return false;
  return true;
}

// The values of one "vary" entry: a non-empty list, or a range {from, to, count[, scale]}.
std::vector<json> values_of(const std::string& path, const json& v,
                            std::vector<ControlIssue>* issues) {
  if (v.is_array()) {
    if (v.empty()) issues->push_back({path, "an empty list: give at least one value"});
    if (v.size() > static_cast<size_t>(kMaxSweepCases))
      issues->push_back(
          {path, std::to_string(v.size()) + " values: at most " + std::to_string(kMaxSweepCases)});
    return std::vector<json>(v.begin(), v.end());
  }
  if (!v.is_object()) {
    issues->push_back({path, show(v) + " is neither a list of values nor a range {\"from\": A, "
                                       "\"to\": B, \"count\": N}"});
    return {};
  }
  const size_t before = issues->size();
  for (const auto& [k, _] : v.items())
    if (k != "from" && k != "to" && k != "count" && k != "scale") {
      const std::string s = schema::suggestion(k, {"from", "to", "count", "scale"});
      issues->push_back({path + "." + k, "unknown key in a range (from, to, count, scale)" +
                                             (s.empty() ? "" : "; did you mean \"" + s + "\"?")});
    }
  const auto number = [&](const char* k) -> double {
    if (!v.contains(k) || !v[k].is_number()) {
      issues->push_back({path + "." + k, std::string("a range needs \"") + k + "\" as a number" +
                                             (v.contains(k) ? ", got " + show(v[k]) : "")});
      return 0;
    }
    return v[k].get<double>();
  };
  const double from = number("from"), to = number("to");
  long count = 0;
  if (!v.contains("count") || !v["count"].is_number_integer() || v["count"].get<long>() < 2 ||
      v["count"].get<long>() > kMaxSweepCases)
    issues->push_back({path + ".count",
                       "the number of values, an integer in [2, " + std::to_string(kMaxSweepCases) +
                           "]" + (v.contains("count") ? ", got " + show(v["count"]) : "")});
  else
    count = v["count"].get<long>();
  std::string scale = "linear";
  if (v.contains("scale")) {
    if (v["scale"] == "linear" || v["scale"] == "log")
      scale = v["scale"].get<std::string>();
    else
      issues->push_back({path + ".scale", show(v["scale"]) + ": \"linear\" or \"log\""});
  }
  if (scale == "log" && !(from > 0 && to > 0))
    issues->push_back({path, "a log range needs from and to > 0"});
  if (issues->size() > before) return {};
  std::vector<json> out;
  for (long i = 0; i < count; ++i) {
    const double f = static_cast<double>(i) / static_cast<double>(count - 1);
    // (1 - f) from + f to: no overflow between finite ends (-1e308 to 1e308)
    double x = scale == "log" ? std::exp((1 - f) * std::log(from) + f * std::log(to))
                              : (1 - f) * from + f * to;
    if (i == 0) x = from;
    if (i == count - 1) x = to;
    if (!std::isfinite(x)) {
      issues->push_back({path, "value " + std::to_string(i) + " of the range is not finite"});
      return {};
    }
    // 12 significant digits: 0.1 + 2 x 0.1 is written 0.3
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.12g", x);
    out.push_back(json::parse(buf));
  }
  return out;
}

// doc with `key` (dotted) set to v; "" on success, else what is in the way.
std::string set_key(json* doc, const std::string& key, const json& v) {
  json* at = doc;
  const std::vector<std::string> segs = segments(key);
  for (size_t i = 0; i + 1 < segs.size(); ++i) {
    if (!at->contains(segs[i])) (*at)[segs[i]] = json::object();
    at = &(*at)[segs[i]];
    if (!at->is_object())
      return "the base's " + segs[i] + " is " + show(*at) + ", not an object with " + segs[i + 1];
  }
  (*at)[segs.back()] = v;
  return "";
}

json load_base(const json& base, const std::string& base_dir, std::vector<ControlIssue>* issues) {
  if (base.is_object()) return base;
  if (!base.is_string() || base.get<std::string>().empty()) {
    issues->push_back({"base",
                       "the base control: a file name (relative to the sweep file) or a "
                       "control object, got " +
                           show(base)});
    return json();
  }
  fs::path p = base.get<std::string>();
  if (p.is_relative()) p = fs::path(base_dir) / p;
  try {
    json doc = parse_json_strict(read_control_text(p.string()), p.string());
    if (!doc.is_object()) {
      issues->push_back({"base", p.string() + " is not a JSON object"});
      return json();
    }
    return doc;
  } catch (const ControlError& e) {
    issues->push_back({"base", e.what()});
    return json();
  }
}

}  // namespace

SweepPlan parse_sweep(const std::string& text, const std::string& source,
                      const std::string& base_dir, const std::string& default_dir) {
  const json doc = parse_json_strict(text, source);
  if (!doc.is_object())
    throw ControlError(source, {{"",
                                 "a sweep file is a JSON object {\"base\": ..., \"vary\": "
                                 "{...}}, got " +
                                     show(doc)}});
  std::vector<ControlIssue> issues;
  const std::vector<std::string> top = {"base", "vary", "output", "description"};
  for (const auto& [k, _] : doc.items())
    if (k != "base" && k != "vary" && k != "output" && k != "description") {
      const std::string s = schema::suggestion(k, top);
      issues.push_back({k, "unknown key of a sweep file (base, vary, output, description)" +
                               (s.empty() ? "" : "; did you mean \"" + s + "\"?")});
    }
  if (!doc.contains("base")) issues.push_back({"base", "missing: the control file to vary"});
  const json base = doc.contains("base") ? load_base(doc["base"], base_dir, &issues) : json();

  SweepPlan plan;
  plan.dir = default_dir;
  if (doc.contains("output")) {
    const json& o = doc["output"];
    if (!o.is_object())
      issues.push_back({"output", "an object {\"dir\": ...}, got " + show(o)});
    else
      for (const auto& [k, v] : o.items()) {
        if (k != "dir")
          issues.push_back({"output." + k, "unknown key (output.dir is the only one)"});
        else if (!v.is_string() || v.get<std::string>().empty())
          issues.push_back({"output.dir", "a directory name, got " + show(v)});
        else
          plan.dir = v.get<std::string>();
      }
  }

  std::vector<std::vector<json>> values;
  if (!doc.contains("vary") || !doc["vary"].is_object() || doc["vary"].empty()) {
    issues.push_back({"vary",
                      "an object of the keys to vary and their values, e.g. {\"ca\": "
                      "[0.3, 0.6]}" +
                          (doc.contains("vary") ? ", got " + show(doc["vary"]) : "")});
  } else {
    for (const auto& [key, v] : doc["vary"].items()) {
      const std::string path = "vary." + key;
      if (!valid_key(key)) {
        issues.push_back({path, "a key is a dotted path into the control file, e.g. capsule.C"});
        continue;
      }
      if (key == "output" || key.rfind("output.dir", 0) == 0) {
        issues.push_back({path, "the sweep sets each case's output.dir (<dir>/case_NNN)"});
        continue;
      }
      plan.keys.push_back(key);
      values.push_back(values_of(path, v, &issues));
    }
  }
  double total = 1;
  for (const auto& v : values) total *= static_cast<double>(v.size());
  if (!values.empty() && total > kMaxSweepCases)
    issues.push_back({"vary", "the combinations make " + std::to_string(static_cast<long>(total)) +
                                  " cases: at most " + std::to_string(kMaxSweepCases)});
  if (!issues.empty()) throw ControlError(source, issues);

  // Every combination, the last key fastest.
  const int n = static_cast<int>(total);
  int failing = 0;
  for (int c = 0; c < n; ++c) {
    SweepCase sc;
    sc.index = c;
    char name[32];
    std::snprintf(name, sizeof name, "case_%03d", c);
    sc.name = name;
    json control = base;
    int rest = c;
    std::vector<json> chosen(values.size());
    for (int k = static_cast<int>(values.size()) - 1; k >= 0; --k) {
      chosen[k] = values[k][rest % values[k].size()];
      rest /= static_cast<int>(values[k].size());
    }
    std::string in_the_way;
    for (size_t k = 0; k < values.size(); ++k) {
      sc.values.emplace_back(plan.keys[k], chosen[k].dump());
      const std::string why = set_key(&control, plan.keys[k], chosen[k]);
      if (!why.empty() && in_the_way.empty()) in_the_way = "vary." + plan.keys[k] + ": " + why;
    }
    const std::string where = "case " + std::to_string(c) + " (" + sc.label() + ")";
    if (!in_the_way.empty()) {
      if (failing++ < 3) issues.push_back({where, in_the_way});
      continue;
    }
    control["output"]["dir"] = (fs::path(plan.dir) / sc.name).string();
    sc.control_text = control.dump(2) + "\n";
    try {
      parse_control(sc.control_text, where);
    } catch (const ControlError& e) {
      if (failing++ < 3)
        for (const ControlIssue& i : e.issues())
          issues.push_back({where + ": " + i.path, i.message});
      continue;
    }
    plan.cases.push_back(std::move(sc));
  }
  if (failing > 3)
    issues.push_back({"", std::to_string(failing - 3) + " more cases fail (" +
                              std::to_string(failing) + " of " + std::to_string(n) + ")"});
  if (!issues.empty()) throw ControlError(source, issues);
  return plan;
}

SweepPlan load_sweep_file(const std::string& path) {
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  fs::path stem = p;
  stem.replace_extension();
  return parse_sweep(read_control_text(path), path, dir.string(), stem.string());
}

}  // namespace capflow::control
