#include "app/run_directory.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "app/errors.h"
#include "files/atomic_write.h"
#include "files/input_file.h"

namespace capflow::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kLockName = "run.lock";

// Files and folders a run creates (what --overwrite removes; nothing else is touched).
const char* const kRunFiles[] = {"control.json",        "control.json.tmp", "control.source",
                                 "control.source.tmp",  "timeseries.csv",   "steady.csv",
                                 "events.jsonl",        "run.log",          "surface.pvd",
                                 "surface.pvd.tmp",     "preview.png",      "preview.png.tmp",
                                 "timeseries.csv.torn", "steady.csv.torn"};
const char* const kRunFolders[] = {"checkpoints", "frames", "profiles", "vtk"};

std::string errno_text() {
  return std::strerror(errno);
}

[[noreturn]] void write_failed(const fs::path& p, const std::string& why) {
  throw OutputError("cannot write " + p.string() + ": " + why);
}

bool is_empty_but_lock(const fs::path& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().filename() != kLockName) return false;
  return !ec;
}

}  // namespace

AppendFile::~AppendFile() {
  close();
}

void AppendFile::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void AppendFile::open(const fs::path& path, bool truncate) {
  if (fd_ >= 0) ::close(fd_);
  path_ = path;
  struct stat before {};
  if (::stat(path.c_str(), &before) == 0 && !S_ISREG(before.st_mode))
    throw UserError(path.string() + " is " + files::special_kind(before.st_mode) +
                    ": a run's record file must be a regular file");
  // O_NONBLOCK: a FIFO put in a record's place after the check cannot block the open.
  fd_ = ::open(path.c_str(),
               O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NONBLOCK | O_NOCTTY |
                   (truncate ? O_TRUNC : 0),
               0644);
  if (fd_ < 0) write_failed(path, errno_text());
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    throw UserError(path.string() + " is " + files::special_kind(st.st_mode) +
                    ": a run's record file must be a regular file");
  }
}

void AppendFile::append(const std::string& record) {
  if (fd_ < 0) write_failed(path_, "the file is not open");
  const off_t before = ::lseek(fd_, 0, SEEK_END);
  int err = 0;
  if (files::write_all(fd_, record.data(), record.size(), &err)) return;
  // Cut back what part of the record reached the file: never half a row.
  if (before >= 0 && ::ftruncate(fd_, before) != 0) {
    write_failed(path_, std::string(std::strerror(err)) +
                            " (and it could not be cut back to its last whole record: " +
                            errno_text() + ")");
  }
  write_failed(path_, std::strerror(err));
}

namespace {

// A record file opened for reading under files/input_file.h's rule (a regular file; a FIFO left
// in its place is refused at once). The caller closes it.
int open_records_file(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw UserError(path.string() + " is " + files::special_kind(st.st_mode) +
                    ": a run's record file must be a regular file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) write_failed(path, errno_text());
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw UserError(path.string() + " is not a regular file: a run's record file must be one");
  }
  return fd;
}

// Calls f(buffer, n) for every chunk of the file.
template <class F>
void for_each_chunk(int fd, const fs::path& path, F&& f) {
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string why = errno_text();
      ::close(fd);
      write_failed(path, why);
    }
    if (n == 0) return;
    if (!f(buf, n)) return;
  }
}

}  // namespace

AppendFile::Lines AppendFile::count_lines(const fs::path& path) {
  Lines out;
  std::error_code ec;
  if (!fs::exists(path, ec)) return out;
  const int fd = open_records_file(path);
  char last = '\n';
  for_each_chunk(fd, path, [&](const char* b, ssize_t n) {
    for (ssize_t i = 0; i < n; ++i) out.whole += b[i] == '\n';
    last = b[n - 1];
    return true;
  });
  ::close(fd);
  out.torn = last != '\n';
  return out;
}

void AppendFile::keep_lines(long lines, const fs::path& cut_copy) {
  const int fd = open_records_file(path_);
  off_t keep = 0;
  long seen = 0;
  for_each_chunk(fd, path_, [&](const char* b, ssize_t n) {
    for (ssize_t i = 0; i < n && seen < lines; ++i) {
      ++keep;
      if (b[i] == '\n') ++seen;
    }
    return seen < lines;
  });
  if (seen < lines) {
    ::close(fd);
    throw UserError(path_.string() + " has " + std::to_string(seen) +
                    " whole lines, fewer than the " + std::to_string(lines) +
                    " its checkpoint recorded: the file does not belong to "
                    "this run's checkpoints");
  }
  // What is cut off ends in a torn line (a write cut short by a crash or a full disk): it goes to
  // `cut_copy` before the file is cut, so that nothing is lost unseen.
  struct stat st {};
  if (::fstat(fd, &st) == 0 && st.st_size > keep && !cut_copy.empty()) {
    char last = '\n';
    if (::pread(fd, &last, 1, st.st_size - 1) == 1 && last != '\n') {
      std::string tail(static_cast<size_t>(st.st_size - keep), '\0');
      const ssize_t got = ::pread(fd, tail.data(), tail.size(), keep);
      tail.resize(got > 0 ? static_cast<size_t>(got) : 0);
      try {
        files::write_atomically(cut_copy.string(), tail);
      } catch (const files::WriteError& e) {
        ::close(fd);
        throw OutputError(e.what());
      }
    }
  }
  ::close(fd);
  if (::truncate(path_.c_str(), keep) != 0) write_failed(path_, errno_text());
}

RunDirectory::~RunDirectory() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

bool RunDirectory::is_run(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "control.json", ec) &&
         (fs::is_regular_file(dir / "events.jsonl", ec) ||
          fs::is_directory(dir / "checkpoints", ec));
}

std::unique_ptr<RunDirectory> RunDirectory::open(const fs::path& dir, Mode mode) {
  std::unique_ptr<RunDirectory> r(new RunDirectory());
  r->dir_ = dir;
  std::error_code ec;
  const bool exists = fs::exists(dir, ec);
  if (exists && !fs::is_directory(dir, ec))
    throw UserError("run directory " + dir.string() + " exists and is not a directory");
  if (mode == Mode::Resume) {
    if (!exists) throw UserError(dir.string() + ": no such run directory");
    if (!is_run(dir))
      throw UserError(dir.string() +
                      " is not a capflow run directory (no control.json with "
                      "events.jsonl or checkpoints/)");
  } else if (exists && !is_empty_but_lock(dir)) {
    if (!is_run(dir))
      throw UserError("run directory " + dir.string() +
                      " is not empty and is not a capflow run: "
                      "give a new or empty directory (output.dir or -o)");
    if (mode == Mode::Create)
      throw UserError("run directory " + dir.string() +
                      " already holds a capflow run: continue it "
                      "with --resume " +
                      dir.string() + ", or replace it with --overwrite");
  }
  if (!exists) {
    fs::create_directories(dir, ec);
    if (ec)
      throw UserError("cannot create the run directory " + dir.string() + ": " + ec.message());
    r->created_ = true;
  }
  try {
    r->lock(mode);
  } catch (...) {
    if (r->created_) {  // nothing of this run stays behind
      if (r->lock_fd_ >= 0) ::close(r->lock_fd_);
      r->lock_fd_ = -1;
      fs::remove(dir / kLockName, ec);
      fs::remove(dir, ec);
    }
    throw;
  }
  if (mode == Mode::Overwrite) r->remove_run_files();
  return r;
}

void RunDirectory::lock(Mode mode) {
  const fs::path p = dir_ / kLockName;
  lock_fd_ = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NONBLOCK | O_NOCTTY, 0644);
  if (lock_fd_ < 0)
    throw UserError("cannot open the lock file " + p.string() +
                    " of the run directory: " + errno_text());
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char buf[32] = {0};
    const ssize_t n = ::pread(lock_fd_, buf, sizeof buf - 1, 0);
    const std::string pid =
        n > 0 ? std::string(buf, static_cast<size_t>(n)) : std::string("unknown");
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (err != EWOULDBLOCK)
      throw UserError("cannot lock the run directory " + dir_.string() + ": " + std::strerror(err));
    std::string holder = pid;
    holder.erase(std::remove_if(holder.begin(), holder.end(), [](char c) { return c == '\n'; }),
                 holder.end());
    throw UserError("run directory " + dir_.string() +
                    " is in use by another capflow process (PID " + holder + ")" +
                    (mode == Mode::Resume ? ": a run can be resumed once it has ended"
                                          : ": wait for it to end, or stop it first"));
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) < 0)
    write_failed(dir_ / kLockName, errno_text());
}

void RunDirectory::abandon() {
  timeseries_.close();
  steady_.close();
  events_.close();
  log_.close();
  remove_run_files();
  std::error_code ec;
  if (lock_fd_ >= 0) {
    fs::remove(dir_ / kLockName, ec);
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
  if (created_) fs::remove(dir_, ec);  // only when empty
}

void RunDirectory::remove_run_files() const {
  std::error_code ec;
  for (const char* f : kRunFiles) fs::remove(dir_ / f, ec);
  for (const char* d : kRunFolders) fs::remove_all(dir_ / d, ec);
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("movie", 0) == 0 && e.path().extension() == ".mp4") fs::remove(e.path(), ec);
  }
}

void RunDirectory::open_records(bool fresh, const std::string& timeseries_header,
                                const std::string& steady_header) {
  timeseries_.open(dir_ / "timeseries.csv", fresh);
  steady_.open(dir_ / "steady.csv", fresh);
  events_.open(dir_ / "events.jsonl", fresh);
  log_.open(dir_ / "run.log", fresh);
  if (fresh) {
    timeseries_.append(timeseries_header);
    steady_.append(steady_header);
  }
}

void RunDirectory::write_text(const std::string& name, const std::string& text) const {
  try {
    files::write_atomically((dir_ / name).string(), text);
  } catch (const files::WriteError& e) {
    throw OutputError(e.what());
  }
}

void RunDirectory::sync() const {
  try {
    files::sync_file_system(dir_.string());
  } catch (const files::WriteError& e) {
    throw OutputError(e.what());
  }
}

fs::path RunDirectory::subdirectory(const std::string& name) const {
  const fs::path p = dir_ / name;
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec) write_failed(p, ec.message());
  return p;
}

fs::path RunDirectory::checkpoint_path(long steps) const {
  char name[64];
  std::snprintf(name, sizeof name, "ckpt_%010ld.ckpt", steps);
  return dir_ / "checkpoints" / name;
}

std::vector<fs::path> RunDirectory::checkpoints(const fs::path& dir) {
  std::vector<fs::path> all;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "checkpoints", ec))
    if (e.path().extension() == ".ckpt") all.push_back(e.path());
  std::sort(all.rbegin(), all.rend());
  return all;
}

void RunDirectory::prune_checkpoints(int keep) const {
  const std::vector<fs::path> all = checkpoints(dir_);
  std::error_code ec;
  for (size_t k = static_cast<size_t>(keep); k < all.size(); ++k) fs::remove(all[k], ec);
  for (const auto& e : fs::directory_iterator(dir_ / "checkpoints", ec))
    if (e.path().extension() == ".tmp") fs::remove(e.path(), ec);
}

}  // namespace capflow::app
