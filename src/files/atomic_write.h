// capflow/files/atomic_write: replacing a file so that readers (and a crash) see the old content
// or the new one, never a part: the bytes go to a temporary file beside it, which is renamed over
// the file once it is complete.
//
//   temporary   <path>.tmp, or <path>.<pid>.tmp with unique_temp (several processes may write
//               the same file: the ranks of a sweep)
//   sync        fsync the temporary file before the rename and the directory after it
//               (checkpoints: the newest must survive a power cut or a journal abort)
// A failed write (disk full, read-only, a file-size limit, permissions) removes the temporary
// file and throws WriteError naming `path` and the cause; the old file is left as it was.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace capflow::files {

struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct AtomicWrite {
  bool sync = false;
  bool unique_temp = false;
};

void write_atomically(const std::string& path, std::string_view data, AtomicWrite how = {});

// Everything written to the file system that holds `path` on stable storage (syncfs): what a
// checkpoint counts is written before it is. WriteError naming `path` on an I/O error.
void sync_file_system(const std::string& path);

// Writes all of data to fd (retrying short writes and EINTR); false with *err set (errno, or
// ENOSPC when a write wrote nothing) when it could not.
bool write_all(int fd, const char* data, std::size_t n, int* err);

}  // namespace capflow::files
