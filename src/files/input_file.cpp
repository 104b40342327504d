// capflow/files/input_file: see input_file.h.
#include "files/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "files/printable.h"

namespace capflow::files {

InputError::InputError(const std::string& file, const std::string& problem)
    : std::runtime_error(printable(file) + ": " + problem), file_(file), problem_(problem) {}

std::string special_kind(unsigned mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string size_text(std::size_t bytes) {
  constexpr std::size_t kMiB = std::size_t{1} << 20, kGiB = std::size_t{1} << 30;
  if (bytes >= kGiB && bytes % kGiB == 0) return std::to_string(bytes / kGiB) + " GiB";
  if (bytes >= kMiB && bytes % kMiB == 0) return std::to_string(bytes / kMiB) + " MiB";
  if (bytes >= 10 * kMiB) return "about " + std::to_string((bytes + kMiB / 2) / kMiB) + " MiB";
  return std::to_string(bytes) + " bytes";
}

InputFile::InputFile(const std::string& path, const std::string& what, std::size_t max_bytes)
    : path_(path), what_(what) {
  // Special files are refused before they are opened (opening some devices has effects), and
  // again on the open descriptor (the path may have changed in between).
  struct stat before {};
  if (::stat(path.c_str(), &before) == 0) {
    const std::string kind = special_kind(before.st_mode);
    if (!kind.empty())
      throw InputError(path, "is " + kind + ": a " + what + " must be a regular file");
  }
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd_ < 0)
    throw InputError(path, std::string("cannot open the file: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const std::string err = std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    throw InputError(path, "cannot read the file: " + err);
  }
  const std::string kind = special_kind(st.st_mode);
  if (!kind.empty()) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(path, "is " + kind + ": a " + what + " must be a regular file");
  }
  size_ = static_cast<std::size_t>(st.st_size);
  if (size_ > max_bytes) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(path, "is " + size_text(size_) + ", larger than " + size_text(max_bytes) +
                               ", the largest " + what + " capflow reads");
  }
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::string InputFile::read_range(std::size_t from, std::size_t n) {
  std::string out(n, '\0');
  std::size_t got = 0;
  while (got < n) {
    const ssize_t r = ::pread(fd_, out.data() + got, n - got, static_cast<off_t>(from + got));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0)
      throw InputError(path_, std::string("cannot read the file: ") + std::strerror(errno));
    if (r == 0) break;  // the file shrank since it was opened
    got += static_cast<std::size_t>(r);
  }
  out.resize(got);
  return out;
}

std::string InputFile::read_prefix(std::size_t n) {
  return read_range(0, n < size_ ? n : size_);
}

std::string InputFile::read_all() {
  return read_range(0, size_);
}

std::string read_input_file(const std::string& path, const std::string& what,
                            std::size_t max_bytes) {
  return InputFile(path, what, max_bytes).read_all();
}

}  // namespace capflow::files
