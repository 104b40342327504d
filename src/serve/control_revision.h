// capflow/serve/control_revision: the run's control file as the console sees it, with a revision
// number that grows by one with every change of its bytes that the server sees - its own edits
// and hand edits alike (the page polls at least once a second, so a hand edit shows up within
// one). An edit from the page (submit) is checked against the revision it was made at and the
// schema (control/live_patch.h), then written by atomic replace; the run takes it from the file
// as it takes a hand edit (app/control_feed.h). Submissions are serialised.
#pragma once

#include <mutex>
#include <string>

#include "control/live_patch.h"

namespace capflow::serve {

class ControlRevision {
 public:
  ControlRevision(std::string path, control::Command command)
      : path_(std::move(path)), command_(command) {}

  struct Current {
    long revision = 0;
    std::string text;   // the file's bytes ("" when it cannot be read)
    std::string error;  // why it cannot be read
  };
  Current current();

  // The edit `body` ({"revision", "patch"}) checked and, when it is accepted, written.
  // `refuse`: a reason to refuse every edit now (the run has ended), or "".
  control::LivePatch submit(const std::string& body, const std::string& refuse,
                            long* revision_after);

  const std::string& path() const { return path_; }

 private:
  Current read_locked();
  std::string path_;
  control::Command command_;
  std::mutex mutex_;
  long revision_ = 0;
  std::string last_;
  bool seen_ = false;
};

}  // namespace capflow::serve
