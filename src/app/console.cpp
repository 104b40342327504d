// capflow/app/console: see console.h.
#include "app/console.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>

#include "files/atomic_write.h"
#include "files/printable.h"

namespace capflow::app::console {

namespace {

struct Stream {
  int fd;
  bool gone = false;
  std::string why;
};

std::mutex& mu() {
  static std::mutex m;
  return m;
}
Stream& stream(int fd) {
  static Stream s_out{1, false, ""}, s_err{2, false, ""};
  return fd == 1 ? s_out : s_err;
}

void write_to(int fd, const std::string& bytes) {
  std::lock_guard<std::mutex> l(mu());
  Stream& s = stream(fd);
  if (s.gone) return;
  int err = 0;
  if (!files::write_all(fd, bytes.data(), bytes.size(), &err)) {
    s.gone = true;
    s.why = std::strerror(err);
  }
}

// Long enough for the longest log line capflow writes (a refused edit lists every problem).
constexpr std::size_t kMaxLine = 64 * 1024;

}  // namespace

void err(const std::string& line) {
  write_to(2, files::printable(line, kMaxLine, /*keep_lines=*/true) + "\n");
}

void out(const std::string& line) {
  write_to(1, files::printable(line, kMaxLine, /*keep_lines=*/true) + "\n");
}

void status(const std::string& line) {
  write_to(2, "\r\033[K" + files::printable(line, kMaxLine));
}

bool err_gone() {
  std::lock_guard<std::mutex> l(mu());
  return stream(2).gone;
}

std::string err_gone_reason() {
  std::lock_guard<std::mutex> l(mu());
  return stream(2).why;
}

void reset() {
  std::lock_guard<std::mutex> l(mu());
  stream(1) = Stream{1, false, ""};
  stream(2) = Stream{2, false, ""};
}

}  // namespace capflow::app::console
