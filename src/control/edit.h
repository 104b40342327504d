// capflow/control/edit: applying a live edit of the control file to a running simulation.
//
// Policy (README, "Steering"; docs/control.md lists each key as live or frozen): an edit is the
// difference between the control file as saved now and as it was read before. Only keys whose
// value changed in the file count, so command-line overrides (-o, --t-end) stay until the user
// edits that key. Each changed key is applied or refused by the schema's mutability:
//   live    applied at the next step boundary (ca, steady.*, time.dt, time.t_end,
//           output.*_every, numerics.volume_correction, numerics.threads, run.*);
//   frozen  refused with a message while the rest of the edit applies - unless the new value
//           is the one the run already has (then nothing changes and nothing is refused).
// An edit that does not parse or validate is refused as a whole before this (the run keeps its
// settings).
#pragma once

#include <string>
#include <vector>

#include "control/options.h"
#include "control/record.h"

namespace capflow::control {

struct OptionChange {
  std::string path;       // e.g. "time.t_end", "ca", "output.mp4"
  std::string old_value;  // JSON text: the run's value before the edit
  std::string new_value;  // JSON text
  std::string reason;     // for refused changes: why
};

// The change as an events.jsonl record: {"old": ..., "new": ...} and, when given, "reason".
Record change_record(const OptionChange& change, const std::string& reason = "");

struct EditResult {
  ControlOptions merged;  // the run's options with the applied changes
  std::vector<OptionChange> applied;
  std::vector<OptionChange> refused;
  bool schedule_changed = false;  // "ca" changed: CaScheduler::edit
  bool steady_changed = false;    // a steady.* key changed: CaScheduler::set_steady
};

// `effective`: the run's options now; `previous`: the control file as last read; `edited`: the
// file as saved now.
EditResult apply_edit(const ControlOptions& effective, const ControlOptions& previous,
                      const ControlOptions& edited);
// The same with previous = effective (every difference from the run's options is a change).
EditResult apply_edit(const ControlOptions& effective, const ControlOptions& edited);

}  // namespace capflow::control
