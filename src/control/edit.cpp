#include "control/edit.h"

#include "control/schema_table.h"

namespace capflow::control {

using schema::json;

namespace {

std::string text_of(const std::optional<json>& v) {
  return v ? v->dump() : "null";
}

const char* const kFrozenReason =
    "cannot change while the run goes on (restart the run to change it)";

std::string not_for(Command c) {
  return std::string("capflow ") + command_name(c) + " does not use it";
}

}  // namespace

const char* outcome_name(EditOutcome o) {
  switch (o) {
    case EditOutcome::Applied:
      return "applied";
    case EditOutcome::Frozen:
      return "frozen";
    case EditOutcome::NotForCommand:
      return "not_for_command";
    case EditOutcome::Invalid:
      return "invalid";
  }
  return "";
}

EditResult apply_edit(const ControlOptions& effective, const ControlOptions& previous,
                      const ControlOptions& edited, const EditPolicy& policy) {
  EditResult r;
  r.merged = effective;
  for (const schema::Field& f : schema::fields()) {
    const std::string before = text_of(f.write(previous)), after = text_of(f.write(edited));
    if (before == after) continue;
    const std::string now = text_of(f.write(effective));
    if (now == after) continue;  // back to (or already at) the run's value
    OptionChange c{f.info.path, now, after, EditOutcome::Applied, ""};
    if (f.info.mutability == Mutability::Frozen || !f.copy) {
      c.outcome = EditOutcome::Frozen;
      c.reason = kFrozenReason;
    } else if (!f.info.live_for(policy.command)) {
      c.outcome = EditOutcome::NotForCommand;
      c.reason = not_for(policy.command);
    } else if (policy.veto) {
      ControlOptions with = r.merged;
      f.copy(with, edited);
      c.reason = policy.veto(c, with);
      if (!c.reason.empty()) c.outcome = EditOutcome::Invalid;
    }
    if (c.outcome != EditOutcome::Applied) {
      r.refused.push_back(c);
      continue;
    }
    f.copy(r.merged, edited);
    if (f.info.path == "ca") r.schedule_changed = true;
    if (f.info.path.rfind("steady.", 0) == 0) r.steady_changed = true;
    r.applied.push_back(c);
  }
  for (const schema::Group& g : schema::groups()) {
    if (!g.toggle) continue;
    const bool before = g.toggle(previous), after = g.toggle(edited), now = g.toggle(effective);
    if (before == after || now == after) continue;
    // Toggle groups are frozen (output.mp4).
    r.refused.push_back({g.path, now ? "true" : "false", after ? "true" : "false",
                         EditOutcome::Frozen, kFrozenReason});
  }
  return r;
}

EditResult apply_edit(const ControlOptions& effective, const ControlOptions& edited,
                      const EditPolicy& policy) {
  return apply_edit(effective, effective, edited, policy);
}

Record change_record(const OptionChange& c) {
  Record r;
  r.set_json("old", c.old_value).set_json("new", c.new_value);
  if (c.outcome != EditOutcome::Applied)
    r.set("refused", outcome_name(c.outcome)).set("reason", c.reason);
  return r;
}

}  // namespace capflow::control
