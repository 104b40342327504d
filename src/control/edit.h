// capflow/control/edit: applying a live edit of the control file to a running command.
//
// Policy (README, "Steering"; docs/control.md lists each key's edit column): an edit is the
// difference between the control file as saved now and as it was read before. Only keys whose
// value changed in the file count, so command-line overrides (-o, --t-end) stay until the user
// edits that key. Each changed key gets one typed outcome:
//   Applied        a key live for this command (the schema's FieldInfo::live_for): applied at
//                  the next step boundary;
//   Frozen         a frozen key (restart the run to change it);
//   NotForCommand  a live key this command does not take (capflow steady's solver uses only a
//                  few);
//   Invalid        a key the policy's veto refuses in this run's state (a continuation in capflow
//                  run; a new continuation.from once capflow steady's branch has started);
// each refusal with its message, while the rest of the edit applies - unless the new value is
// the one the run already has (then nothing changes and nothing is refused). An edit that does
// not parse or validate is refused as a whole before this (control_file.h: its run.* keys are
// still honoured, run_keys_of).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "control/options.h"
#include "control/record.h"
#include "control/schema.h"

namespace capflow::control {

enum class EditOutcome { Applied, Frozen, NotForCommand, Invalid };

struct OptionChange {
  std::string path;       // e.g. "time.t_end", "ca", "output.mp4"
  std::string old_value;  // JSON text: the run's value before the edit
  std::string new_value;  // JSON text
  EditOutcome outcome = EditOutcome::Applied;
  std::string reason;  // refusals: why, for the user
};

// The change as an events.jsonl record: {"old": ..., "new": ...} and, for a refusal, "reason"
// and "refused" (frozen, not_for_command, invalid).
Record change_record(const OptionChange& change);

struct EditPolicy {
  Command command = Command::Run;
  // A change of a key live for the command that this run cannot take now: "" lets it apply,
  // otherwise the message of its Invalid refusal. `merged`: the options with it applied.
  std::function<std::string(const OptionChange& change, const ControlOptions& merged)> veto;
};

struct EditResult {
  ControlOptions merged;              // the run's options with the applied changes
  std::vector<OptionChange> applied;  // outcome Applied, in table order
  std::vector<OptionChange> refused;  // every other outcome, in table order
  bool schedule_changed = false;      // "ca" applied: CaScheduler::edit
  bool steady_changed = false;        // a steady.* key applied: CaScheduler::set_steady
  bool empty() const { return applied.empty() && refused.empty(); }
};

// `effective`: the run's options now; `previous`: the control file as last read; `edited`: the
// file as saved now.
EditResult apply_edit(const ControlOptions& effective, const ControlOptions& previous,
                      const ControlOptions& edited, const EditPolicy& policy = {});
// The same with previous = effective (every difference from the run's options is a change).
EditResult apply_edit(const ControlOptions& effective, const ControlOptions& edited,
                      const EditPolicy& policy = {});

// "applied", "frozen", "not_for_command", "invalid".
const char* outcome_name(EditOutcome o);

}  // namespace capflow::control
