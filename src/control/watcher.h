// capflow/control/watcher: notices when the control file is saved.
//
// Uses inotify on the file's DIRECTORY (so editors that save by writing a temporary file and
// renaming it over the original are seen: IN_MOVED_TO / IN_CREATE / IN_CLOSE_WRITE on the
// name), and falls back to polling the file's (inode, size, mtime) when inotify is unavailable
// or forced. changed() never blocks; it reports a change once the file has been stable for
// `settle_ms` (so a half-written file is not read).
#pragma once

#include <sys/types.h>

#include <string>

namespace capflow::control {

class FileWatcher {
 public:
  explicit FileWatcher(std::string path, bool force_polling = false, int settle_ms = 50);
  ~FileWatcher();
  FileWatcher(const FileWatcher&) = delete;
  FileWatcher& operator=(const FileWatcher&) = delete;

  // True once per save (after the file settled).
  bool changed();
  bool using_inotify() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

 private:
  struct Stamp {
    ino_t ino = 0;
    off_t size = -1;
    long long mtime_ns = -1;
    bool operator!=(const Stamp& o) const { return ino != o.ino || size != o.size || mtime_ns != o.mtime_ns; }
  };
  Stamp stamp() const;

  std::string path_, dir_, name_;
  int fd_ = -1, wd_ = -1;
  int settle_ms_;
  Stamp last_;
  bool pending_ = false;
  long long pending_since_ms_ = 0;
  Stamp pending_stamp_;
};

}  // namespace capflow::control
