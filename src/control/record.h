// capflow/control/record: JSON objects written by capflow (events.jsonl lines, `capflow shape`
// output), built field by field without exposing a JSON library: nlohmann-json stays inside
// src/control.
//
//   Record r;
//   r.set("event", "edit").set("accepted", true).set("t", 0.25);
//   r.set_json("control", effective_control_text);   // a value that is JSON text already
//   Record applied;  applied.set("ca", Record().set_json("old", "0.3").set_json("new", "0.5"));
//   std::string line = r.text();    // {"event":"edit","accepted":true,"t":0.25,...} (one line)
// Keys keep their insertion order; setting a key again replaces its value in place. Doubles are
// written to round-trip (17 significant digits where needed); NaN and infinities as null.
// Strings are UTF-8; invalid bytes are replaced (U+FFFD) rather than refused.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace capflow::control {

class Record {
 public:
  Record& set(const std::string& key, double v);
  Record& set(const std::string& key, int v) { return set(key, static_cast<long long>(v)); }
  Record& set(const std::string& key, long v) { return set(key, static_cast<long long>(v)); }
  Record& set(const std::string& key, long long v);
  Record& set(const std::string& key, bool v);
  Record& set(const std::string& key, const char* v) { return set(key, std::string(v)); }
  Record& set(const std::string& key, const std::string& v);
  Record& set(const std::string& key, const std::vector<std::string>& v);
  Record& set(const std::string& key, const std::vector<double>& v);
  Record& set(const std::string& key, const Record& object);
  // `json_text` must be one JSON value (it is parsed and re-written: invalid text is stored as
  // a string instead).
  Record& set_json(const std::string& key, const std::string& json_text);

  // Every field of `other` set here (in its order).
  Record& merge(const Record& other);

  bool empty() const { return fields_.empty(); }
  // One line of JSON (compact), or indented by `indent` spaces per level when indent >= 0.
  std::string text(int indent = -1) const;

 private:
  Record& put(const std::string& key, std::string json_value);
  std::vector<std::pair<std::string, std::string>> fields_;  // key, JSON text of the value
};

// `text` as one compact JSON value when it is one (a line of events.jsonl, a control file),
// else as a JSON string holding it.
std::string json_value_text(const std::string& text);

}  // namespace capflow::control
