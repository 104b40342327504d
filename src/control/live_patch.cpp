#include "control/live_patch.h"

#include "control/control_file.h"
#include "control/limits.h"
#include "control/schema_table.h"

namespace capflow::control {

using schema::json;

namespace {

std::string join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

// True when `path` is a group of the schema or the parent of one of its fields.
bool is_object_path(const std::string& path) {
  if (schema::find_group(path)) return true;
  const std::string prefix = path + ".";
  for (const schema::Field& f : schema::fields())
    if (f.info.path.compare(0, prefix.size(), prefix) == 0) return true;
  return false;
}

std::string refusal(const FieldInfo& info, Command command) {
  if (info.mutability == Mutability::Frozen)
    return "cannot change while the run goes on (restart the run to change it)";
  return std::string("capflow ") + command_name(command) + " does not use it";
}

// The schema paths the patch names, each checked: refusals into *issues.
void walk(const json& patch, const std::string& at, Command command,
          std::vector<std::string>* keys, std::vector<ControlIssue>* issues) {
  for (auto it = patch.begin(); it != patch.end(); ++it) {
    const std::string path = join(at, it.key());
    if (const schema::Field* f = schema::find_field(path)) {
      keys->push_back(path);
      if (!f->info.live_for(command)) issues->push_back({path, refusal(f->info, command)});
    } else if (is_object_path(path) && it.value().is_object()) {
      walk(it.value(), path, command, keys, issues);
    } else if (is_object_path(path)) {
      issues->push_back({path, "a live edit changes the keys of this object one by one"});
    } else {
      issues->push_back({path, "is not a key of the control file (docs/control.md)"});
    }
  }
}

LivePatch fail(LivePatch::Status s, std::vector<ControlIssue> issues) {
  LivePatch r;
  r.status = s;
  r.issues = std::move(issues);
  return r;
}

}  // namespace

const char* status_name(LivePatch::Status s) {
  switch (s) {
    case LivePatch::Status::Ok:
      return "ok";
    case LivePatch::Status::BadRequest:
      return "bad_request";
    case LivePatch::Status::Stale:
      return "stale";
    case LivePatch::Status::Refused:
      return "refused";
  }
  return "";
}

LivePatch apply_live_patch(const std::string& file_text, long revision,
                           const std::string& request_body, Command command) {
  using S = LivePatch::Status;
  if (request_body.size() > kMaxControlBytes)
    return fail(S::BadRequest, {{"", "the request is larger than the control file may be"}});
  json body = json::parse(request_body, nullptr, false);
  if (body.is_discarded() || !body.is_object())
    return fail(S::BadRequest, {{"", "the body must be a JSON object {\"revision\": R, "
                                     "\"patch\": {...}}"}});
  const auto rev = body.find("revision");
  if (rev == body.end() || !rev->is_number_integer())
    return fail(S::BadRequest, {{"revision", "must be the integer revision of the control file "
                                             "the edit was made against"}});
  const auto patch = body.find("patch");
  if (patch == body.end() || !patch->is_object())
    return fail(S::BadRequest, {{"patch", "must be a JSON merge patch object of live keys"}});
  for (auto it = body.begin(); it != body.end(); ++it)
    if (it.key() != "revision" && it.key() != "patch")
      return fail(S::BadRequest, {{it.key(), "is not a field of an edit (revision, patch)"}});
  if (rev->get<long long>() != revision)
    return fail(S::Stale, {{"revision", "the control file is at revision " +
                                            std::to_string(revision) + ", the edit was made at " +
                                            std::to_string(rev->get<long long>())}});

  LivePatch r;
  walk(*patch, "", command, &r.keys, &r.issues);
  if (!r.issues.empty()) {
    r.status = S::Refused;
    return r;
  }
  json file = json::parse(file_text, nullptr, false, true);
  if (file.is_discarded() || !file.is_object())
    return fail(S::Refused, {{"", "the control file on disk is not a JSON object; fix it by hand"}});
  file.merge_patch(*patch);
  r.text = file.dump(2) + "\n";
  try {
    parse_control(r.text, "the edited control file");
  } catch (const ControlError& e) {
    r.status = S::Refused;
    r.issues = e.issues();
    r.text.clear();
    return r;
  }
  r.status = S::Ok;
  return r;
}

std::string live_fields_json(Command command) {
  json a = json::array();
  for (const schema::Field& f : schema::fields()) {
    if (!f.info.live_for(command)) continue;
    a.push_back({{"path", f.info.path},
                 {"type", f.info.type},
                 {"valid", f.info.valid},
                 {"default", f.info.default_value},
                 {"unit", f.info.unit},
                 {"doc", f.info.doc}});
  }
  return a.dump();
}

}  // namespace capflow::control
