// capflow/files/input_file: the one rule for every file capflow reads - control files, sweep
// files, checkpoints, ParaView surfaces and collections, CSV tables, event logs, run-directory
// notes.
//
//   * A regular file only. Symlinks are followed; what they end at must be a regular file too. A
//     FIFO, a device (/dev/zero), a socket or a directory is refused before any byte is read.
//   * Opened with O_NONBLOCK and checked with fstat on the open descriptor (no window between a
//     check and the open), so that opening a FIFO cannot block.
//   * Its size is known before its body is read: a file larger than the reader's bound is refused
//     without reading it (a sparse 2 GiB file costs nothing), and a reader can check a header
//     (read_prefix) before it reads the rest.
//   * read_all() reads at most the size fstat gave: a file that grows while it is read (the CSV of
//     a live run) yields the part that existed when it was opened.
// Failures throw InputError, whose message names the file and what is wrong with it; the app
// reports it as invalid input (exit 2).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace capflow::files {

// what() is "<file>: <problem>" (the file name made printable).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem);
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_, problem_;
};

class InputFile {
 public:
  // `what` names the kind of file in messages ("checkpoint", "ParaView surface"); `max_bytes` is
  // the largest file this reader takes.
  InputFile(const std::string& path, const std::string& what, std::size_t max_bytes);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  std::size_t size() const { return size_; }
  const std::string& path() const { return path_; }
  // The first min(n, size()) bytes (the header), without reading further.
  std::string read_prefix(std::size_t n);
  // The whole file as it was when opened (size() bytes at most).
  std::string read_all();
  // The file descriptor (owned by this object), positioned at the start.
  int fd() const { return fd_; }

 private:
  std::string read_range(std::size_t from, std::size_t n);
  std::string path_, what_;
  int fd_ = -1;
  std::size_t size_ = 0;
};

// InputFile(path, what, max_bytes).read_all().
std::string read_input_file(const std::string& path, const std::string& what,
                            std::size_t max_bytes);

// "a FIFO", "a device", "a directory", "a socket" or "" for a regular file (st_mode).
std::string special_kind(unsigned mode);

// A size as people read it: "812 bytes", "3 MiB".
std::string size_text(std::size_t bytes);

}  // namespace capflow::files
