// capflow/control/schema: look-ups in the field table (fields, groups, names, did-you-mean).
#include "control/schema.h"

#include <algorithm>
#include <cctype>
#include <limits>

#include "control/schema_builders.h"
#include "control/schema_table.h"

namespace capflow::control::schema {

namespace {

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

std::string parent_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? "" : path.substr(0, dot);
}
std::string leaf_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

}  // namespace

const std::vector<Field>& fields() {
  static const std::vector<Field> t = with_live_commands(detail::build_fields());
  return t;
}

const std::vector<Group>& groups() {
  static const std::vector<Group> g = detail::build_groups();
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

}  // namespace capflow::control
