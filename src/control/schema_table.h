// capflow/control/schema_table: the field table's behaviour (internal to src/control: it uses
// nlohmann::json). schema.h has the public, JSON-free view of the same table.
//
// A Field reads its JSON value into ControlOptions (reporting problems with its path), writes
// its value back (the effective control file; nullopt = omitted), and copies its value between
// two option sets (a live edit). A Group is an object of fields ("time", "output.mp4"); a group
// with a toggle may also be given as true/false (output.mp4).
#pragma once

#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "control/control_error.h"
#include "control/options.h"
#include "control/schema.h"

namespace capflow::control::schema {

using json = nlohmann::json;

struct ReadContext {
  ControlOptions& options;
  std::vector<ControlIssue>& errors;
  std::vector<ControlIssue>& warnings;
};

struct Field {
  FieldInfo info;
  std::function<void(const json& value, ReadContext& ctx)> read;
  std::function<std::optional<json>(const ControlOptions& o)> write;
  std::function<void(ControlOptions& dst, const ControlOptions& src)> copy;
};

struct Group {
  std::string path;  // "" is the document itself
  std::string doc;
  std::function<void(ControlOptions&, bool)> set_toggle;  // empty: an object only
  std::function<bool(const ControlOptions&)> toggle;      // false: written as false
};

const std::vector<Field>& fields();
const std::vector<Group>& groups();
const Field* find_field(const std::string& path);
const Group* find_group(const std::string& path);

// Names directly under `group` ("" = the root): fields and sub-groups, in table order.
std::vector<std::string> names_under(const std::string& group);

// A value shown in a message (cut at 60 characters).
std::string show(const json& v);
// The closest of `options` to `word` within a small edit distance, or "".
std::string suggestion(const std::string& word, const std::vector<std::string>& options);

}  // namespace capflow::control::schema
