#include "control/record.h"

#include <nlohmann/json.hpp>

namespace capflow::control {

using ordered = nlohmann::ordered_json;

namespace {
std::string dump(const ordered& v) {
  return v.dump(-1, ' ', false, ordered::error_handler_t::replace);
}
}  // namespace

Record& Record::put(const std::string& key, std::string json_value) {
  for (auto& f : fields_)
    if (f.first == key) {
      f.second = std::move(json_value);
      return *this;
    }
  fields_.emplace_back(key, std::move(json_value));
  return *this;
}

Record& Record::set(const std::string& key, double v) {
  return put(key, dump(ordered(v)));
}
Record& Record::set(const std::string& key, long long v) {
  return put(key, dump(ordered(v)));
}
Record& Record::set(const std::string& key, bool v) {
  return put(key, v ? "true" : "false");
}
Record& Record::set(const std::string& key, const std::string& v) {
  return put(key, dump(ordered(v)));
}
Record& Record::set(const std::string& key, const std::vector<std::string>& v) {
  return put(key, dump(ordered(v)));
}
Record& Record::set(const std::string& key, const std::vector<double>& v) {
  return put(key, dump(ordered(v)));
}
Record& Record::set(const std::string& key, const Record& object) {
  return put(key, object.text());
}

Record& Record::merge(const Record& other) {
  for (const auto& [k, v] : other.fields_) put(k, v);
  return *this;
}

Record& Record::set_json(const std::string& key, const std::string& json_text) {
  const ordered v = ordered::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (v.is_discarded()) return set(key, json_text);
  return put(key, dump(v));
}

std::string json_value_text(const std::string& text) {
  const ordered v = ordered::parse(text, nullptr, /*allow_exceptions=*/false);
  if (v.is_discarded()) return ordered(text).dump(-1, ' ', false, ordered::error_handler_t::replace);
  return dump(v);
}

std::string Record::text(int indent) const {
  ordered o = ordered::object();
  for (const auto& [key, value] : fields_) o[key] = ordered::parse(value);
  return o.dump(indent, ' ', false, ordered::error_handler_t::replace);
}

}  // namespace capflow::control
