#include "serve/control_revision.h"

#include "control/control_file.h"
#include "files/atomic_write.h"

namespace capflow::serve {

ControlRevision::Current ControlRevision::read_locked() {
  Current c;
  try {
    c.text = control::read_control_text(path_);
  } catch (const std::exception& e) {
    c.error = e.what();
  }
  if (!seen_ || c.text != last_) {
    revision_ += seen_ ? 1 : 0;
    seen_ = true;
    last_ = c.text;
  }
  c.revision = revision_;
  return c;
}

ControlRevision::Current ControlRevision::current() {
  std::lock_guard<std::mutex> lock(mutex_);
  return read_locked();
}

control::LivePatch ControlRevision::submit(const std::string& body, const std::string& refuse,
                                           long* revision_after) {
  std::lock_guard<std::mutex> lock(mutex_);
  const Current c = read_locked();
  *revision_after = c.revision;
  control::LivePatch p;
  if (!refuse.empty()) {
    p.status = control::LivePatch::Status::Refused;
    p.issues.push_back({"", refuse});
    return p;
  }
  if (!c.error.empty()) {
    p.status = control::LivePatch::Status::Refused;
    p.issues.push_back({"", c.error});
    return p;
  }
  p = control::apply_live_patch(c.text, c.revision, body, command_);
  if (p.status != control::LivePatch::Status::Ok) return p;
  try {
    files::write_atomically(path_, p.text);
  } catch (const std::exception& e) {
    p.status = control::LivePatch::Status::Refused;
    p.issues.push_back({"", std::string("cannot write the control file: ") + e.what()});
    return p;
  }
  last_ = p.text;
  *revision_after = ++revision_;
  return p;
}

}  // namespace capflow::serve
