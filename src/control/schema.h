// capflow/control/schema: the control file's fields as data.
//
// One table (schema_fields.cpp) lists every field of the control file with its JSON path, type,
// valid range, default, unit, whether it may change while a run goes on, and a one-line doc. The
// same table drives parsing and validation (control_file.cpp), the effective control file
// (to_json_text), the live-edit policy (edit.cpp), the fuzzing dictionary
// (tests/fuzz/control.dict) and the reference docs/control.md; tests fail when either file is
// stale (`capflow reference` regenerates them).
#pragma once

#include <string>
#include <vector>

namespace capflow::control {

enum class Mutability {
  Frozen,  // fixed for a run's life: a live edit of it is refused (the rest of the edit applies)
  Live,    // a live edit applies at the next step boundary (of the commands in live_in)
};

// The commands that take live edits, as bits of FieldInfo::live_in.
enum class Command : unsigned { Run = 1, Steady = 2 };
constexpr unsigned bit(Command c) {
  return static_cast<unsigned>(c);
}
const char* command_name(Command c);  // "run", "steady"

struct FieldInfo {
  std::string path;           // JSON path, e.g. "time.dt"
  std::string type;           // "number", "integer", "boolean", "string", "choice", ...
  std::string valid;          // the valid values, e.g. "[1e-06, 0.1]", "\"cube\" | \"box\""
  std::string default_value;  // JSON text of the default, or a phrase ("required")
  std::string unit;           // "1/G", "a", "Gs", "px", "" (dimensionless or none)
  Mutability mutability = Mutability::Frozen;
  std::string doc;  // one line
  // Live keys: the commands whose runs take an edit of it (bits of Command). A live key that a
  // command does not use is refused there as not for that command (capflow steady solves with
  // ca, steady.solve_tolerance, time.tolerance and run.state only).
  unsigned live_in = 0;
  bool live_for(Command c) const { return mutability == Mutability::Live && (live_in & bit(c)); }
};

// Every field, in table order (objects in the order of the effective control file).
const std::vector<FieldInfo>& control_fields();

// docs/control.md: the generated reference (every field, the limits, the edit policy).
std::string control_reference_markdown();
// tests/fuzz/control.dict: every key and every string value of the schema, for libFuzzer.
std::string control_fuzz_dictionary();

}  // namespace capflow::control
