#include "control/json_input.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <set>
#include <vector>

#include "control/limits.h"
#include "files/input_file.h"

namespace capflow::control {

using json = nlohmann::json;

namespace {

// Builds the DOM like nlohmann's own SAX DOM parser, but knows where it is (the JSON path of the
// value being parsed) and stops at the first violation of the rules above.
class StrictBuilder {
 public:
  json root;
  ControlIssue issue;  // set when a handler returned false
  bool failed = false;

  static std::string shorten(const std::string& token) {
    return token.size() <= 40 ? token : token.substr(0, 37) + "...";
  }

  bool null() { return put(json(nullptr)); }
  bool boolean(bool v) { return put(json(v)); }
  bool number_integer(json::number_integer_t v) { return put(json(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return put(json(v)); }
  bool number_float(json::number_float_t v, const std::string& token) {
    if (!std::isfinite(v))
      return fail("number " + shorten(token) + " is outside the range of a double");
    return put(json(v));
  }
  bool string(std::string& v) { return put(json(std::move(v))); }
  bool binary(json::binary_t&) { return fail("binary values are not JSON text"); }
  bool start_object(std::size_t) { return open(json::object()); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool key(std::string& k) {
    Frame& f = stack_.back();
    if (!f.keys.insert(k).second) {
      f.key = k;
      return fail("key \"" + k + "\" is given twice in this object (the second would silently " +
                  "replace the first): keep one");
    }
    f.key = std::move(k);
    return true;
  }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool parse_error(std::size_t, const std::string& token, const nlohmann::detail::exception& e) {
    if (e.id == 406) return fail("number " + shorten(token) + " is outside the range of a double");
    failed = true;
    issue = {"", std::string("not valid JSON: ") + e.what()};
    return false;
  }

 private:
  struct Frame {
    json* value;
    std::string key;  // objects: the key of the value being parsed
    std::set<std::string> keys;
  };
  std::vector<Frame> stack_;

  // The JSON path of the value being parsed, e.g. "ca[2].ramp".
  std::string path() const {
    std::string p;
    for (size_t i = 0; i < stack_.size(); ++i) {
      const Frame& f = stack_[i];
      if (f.value->is_array()) {
        // an inner frame's current element is its last one; the innermost one's is being parsed
        const size_t n = f.value->size();
        p += "[" + std::to_string(i + 1 < stack_.size() ? n - 1 : n) + "]";
      } else {
        if (!p.empty()) p += ".";
        p += f.key;
      }
    }
    return p;
  }
  bool fail(const std::string& message) {
    failed = true;
    issue = {path(), message};
    return false;
  }
  json* place(json v) {
    if (stack_.empty()) {
      root = std::move(v);
      return &root;
    }
    json& parent = *stack_.back().value;
    if (parent.is_array()) {
      parent.push_back(std::move(v));
      return &parent.back();
    }
    json& slot = parent[stack_.back().key];
    slot = std::move(v);
    return &slot;
  }
  bool put(json v) {
    place(std::move(v));
    return true;
  }
  bool open(json v) {
    if (static_cast<int>(stack_.size()) >= kMaxControlDepth)
      return fail("nested deeper than " + std::to_string(kMaxControlDepth) +
                  " levels of objects and arrays (a control file needs at most 4)");
    json* p = place(std::move(v));
    stack_.push_back({p, "", {}});
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }
};

}  // namespace

std::string read_control_text(const std::string& path) {
  try {
    return files::read_input_file(path, "control file", kMaxControlBytes);
  } catch (const files::InputError& e) {
    throw ControlError(path, {{"", e.problem()}});
  }
}

json parse_json_strict(const std::string& text, const std::string& source) {
  if (text.size() > kMaxControlBytes)
    throw ControlError(source, {{"", "is " + files::size_text(text.size()) + ", larger than " +
                                         files::size_text(kMaxControlBytes) +
                                         ", the largest control document capflow reads"}});
  StrictBuilder b;
  const bool ok = json::sax_parse(text, &b, json::input_format_t::json, /*strict=*/true);
  if (!ok || b.failed) {
    if (!b.failed) b.issue = {"", "not valid JSON"};
    throw ControlError(source, {b.issue});
  }
  return std::move(b.root);
}

}  // namespace capflow::control
