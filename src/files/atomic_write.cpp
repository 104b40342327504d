// capflow/files/atomic_write: see atomic_write.h.
#include "files/atomic_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "files/printable.h"

namespace capflow::files {

bool write_all(int fd, const char* data, std::size_t n, int* err) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      *err = w < 0 ? errno : ENOSPC;
      return false;
    }
    data += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

void write_atomically(const std::string& path, std::string_view data, AtomicWrite how) {
  const std::string tmp =
      how.unique_temp ? path + "." + std::to_string(::getpid()) + ".tmp" : path + ".tmp";
  const auto fail = [&](const char* step, int err, bool remove_tmp) {
    if (remove_tmp) ::unlink(tmp.c_str());
    throw WriteError("cannot write " + printable(path) + " (" + step + "): " + std::strerror(err));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("create", errno, false);
  int err = 0;
  if (!write_all(fd, data.data(), data.size(), &err)) {
    ::close(fd);
    fail("write", err, true);
  }
  if (how.sync && ::fsync(fd) != 0) {
    err = errno;
    ::close(fd);
    fail("fsync", err, true);
  }
  if (::close(fd) != 0) fail("close", errno, true);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("rename", errno, true);
  if (how.sync) {
    // the rename itself on stable storage: the directory's entry
    const std::string parent = path.find('/') == std::string::npos
                                   ? std::string(".")
                                   : path.substr(0, path.rfind('/') + (path.rfind('/') == 0));
    const int dfd = ::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
      const int r = ::fsync(dfd);
      const int err = errno;
      ::close(dfd);
      if (r != 0) fail("fsync of the directory", err, false);
    }
  }
}

void sync_file_system(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw WriteError("cannot write " + printable(path) + " (sync): " + std::strerror(errno));
  const int r = ::syncfs(fd);
  const int err = errno;
  ::close(fd);
  if (r != 0) throw WriteError("cannot write " + printable(path) + " (sync): " + std::strerror(err));
}

}  // namespace capflow::files
