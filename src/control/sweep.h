// capflow/control/sweep: a sweep file -> the runs it asks for (`capflow sweep`, docs/usage.md).
//
//   {"base": "shear.json",                      a control file (path relative to the sweep
//                                                file) or a control object inline
//    "vary": {"ca": [0.15, 0.3, 0.6],           per key (a dotted path into the control file):
//             "capsule.viscosity_ratio":        a list of values, or a range
//               {"from": 0.2, "to": 5, "count": 3, "scale": "log"}},   (linear or log, count >= 2)
//    "output": {"dir": "runs/sweep_shear"}}     the sweep directory (default: the sweep file's
//                                                name without .json, next to it)
//
// The cases are every combination of the values (the keys in the order written, the last one
// varying fastest). Each case's control file is the base with those keys set and output.dir set
// to <dir>/case_NNN; every case is validated by control/control_file.h, and all problems of all
// cases are reported together (ControlError, paths such as "vary.ca[1]" or "case 3 (ca = 0.6):
// capsule.C: ..."). At most kMaxSweepCases cases.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "control/control_error.h"

namespace capflow::control {

constexpr int kMaxSweepCases = 10000;

struct SweepCase {
  int index = 0;
  std::string name;                                         // case_000
  std::vector<std::pair<std::string, std::string>> values;  // key, value as JSON text
  std::string control_text;   // the case's control file (JSON, indented), output.dir included
  std::string label() const;  // "ca = 0.6, capsule.C = 3"
};

struct SweepPlan {
  std::string dir;                // the sweep directory
  std::vector<std::string> keys;  // the varied keys, in order
  std::vector<SweepCase> cases;
};

// Parses and validates a sweep document; `source` names it and `base_dir` resolves a relative
// "base" path and the default directory. Throws ControlError listing every problem.
SweepPlan parse_sweep(const std::string& text, const std::string& source,
                      const std::string& base_dir, const std::string& default_dir);
// Reads the file through control/json_input.h's gate first.
SweepPlan load_sweep_file(const std::string& path);

}  // namespace capflow::control
