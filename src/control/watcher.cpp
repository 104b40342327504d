#include "control/watcher.h"

#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <filesystem>

namespace capflow::control {

namespace {
long long now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

FileWatcher::FileWatcher(std::string path, bool force_polling, int settle_ms)
    : path_(std::move(path)), settle_ms_(settle_ms) {
  const std::filesystem::path p = std::filesystem::absolute(path_);
  dir_ = p.parent_path().string();
  name_ = p.filename().string();
  if (!force_polling) {
    fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (fd_ >= 0) {
      wd_ = inotify_add_watch(fd_, dir_.c_str(),
                              IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_MODIFY | IN_ATTRIB);
      if (wd_ < 0) {
        ::close(fd_);
        fd_ = -1;
      }
    }
  }
  last_ = stamp();
}

FileWatcher::~FileWatcher() {
  if (fd_ >= 0) ::close(fd_);
}

FileWatcher::Stamp FileWatcher::stamp() const {
  Stamp s;
  struct stat st;
  if (::stat(path_.c_str(), &st) == 0) {
    s.ino = st.st_ino;
    s.size = st.st_size;
    s.mtime_ns = static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  }
  return s;
}

bool FileWatcher::changed() {
  bool touched = false;
  if (fd_ >= 0) {
    alignas(struct inotify_event) char buf[4096];
    for (;;) {
      const ssize_t n = ::read(fd_, buf, sizeof buf);
      if (n <= 0) break;
      for (char* p = buf; p < buf + n;) {
        const auto* ev = reinterpret_cast<const struct inotify_event*>(p);
        if (ev->len > 0 && name_ == ev->name) touched = true;
        p += sizeof(struct inotify_event) + ev->len;
      }
    }
  }
  // Polling covers the fallback and anything inotify coalesced.
  const Stamp s = stamp();
  if (!pending_) {
    if (touched || s != last_) {
      pending_ = true;
      pending_since_ms_ = now_ms();
      pending_stamp_ = s;
    }
    return false;
  }
  if (touched || s != pending_stamp_) {  // still being written
    pending_since_ms_ = now_ms();
    pending_stamp_ = s;
    return false;
  }
  if (now_ms() - pending_since_ms_ >= settle_ms_) {
    pending_ = false;
    last_ = s;
    return true;
  }
  return false;
}

}  // namespace capflow::control
