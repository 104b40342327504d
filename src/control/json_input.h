// capflow/control/json_input: the gate every control document passes (internal to src/control:
// it exposes nlohmann::json, which no other module sees).
//
//   read_control_text(path)   the bytes of a control file under files/input_file.h's rule: a
//                             regular file only (symlinks are followed; a FIFO, device or
//                             directory is refused without blocking), at most kMaxControlBytes
//                             (checked before it is read).
//   parse_json_strict(text)   RFC 8259 JSON into a DOM, refusing with the JSON path of the
//                             problem: nesting deeper than kMaxControlDepth (checked while
//                             parsing, before anything deep is built), a number outside the range
//                             of a double (1e400), a key given twice in one object, and text
//                             larger than kMaxControlBytes.
// Both throw ControlError naming `source`.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "control/control_error.h"

namespace capflow::control {

std::string read_control_text(const std::string& path);
nlohmann::json parse_json_strict(const std::string& text, const std::string& source);

}  // namespace capflow::control
