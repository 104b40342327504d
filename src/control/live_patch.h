// capflow/control/live_patch: an edit of the control file sent by the live console
// (POST /api/control, src/serve) checked and applied to the file's text.
//
// The request body is {"revision": R, "patch": {...}}: R the revision of the control file the edit
// was made against, the patch a JSON merge patch (RFC 7386) of the file. Checked in this order:
//   BadRequest  the body is not such an object (or larger than kMaxControlBytes);
//   Stale       R is not the file's current revision (the page reloads the current values);
//   Refused     a key of the patch is not in the schema, not live for the command (frozen, or a
//               key this command does not use: control/edit.h's reasons), or the patched file
//               does not validate (parse_control's issues, each at its path);
//   Ok          `text`: the patched file (indented JSON), to be written by atomic replace; the run
//               then takes it as it takes a hand edit (app/control_feed.h).
// Nothing here touches a file; JSON is parsed only here, in src/control.
#pragma once

#include <string>
#include <vector>

#include "control/control_error.h"
#include "control/schema.h"

namespace capflow::control {

struct LivePatch {
  enum class Status { Ok, BadRequest, Stale, Refused };
  Status status = Status::BadRequest;
  std::string text;                  // Ok: the control file with the patch applied
  std::vector<std::string> keys;     // the schema paths the patch changes (Ok and Refused)
  std::vector<ControlIssue> issues;  // BadRequest and Refused: why, each at its path
};

LivePatch apply_live_patch(const std::string& file_text, long revision,
                           const std::string& request_body, Command command);

// The live keys of `command` as a JSON array for the console's steering panel:
// [{"path", "type", "valid", "default", "unit", "doc"}, ...] in table order.
std::string live_fields_json(Command command);

// "ok", "bad_request", "stale", "refused".
const char* status_name(LivePatch::Status s);

}  // namespace capflow::control
