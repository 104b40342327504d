// capflow/serve/appended_lines: the whole lines of a file that a run appends to (timeseries.csv,
// events.jsonl), read incrementally: each refresh() reads only the bytes added since the last
// one (through files/input_file.h's rule: a regular file, never blocking). A file that shrank
// (a resume cut it back) or was replaced is read again from the start. A last line without its
// newline (being written) waits for the next refresh. At most kMaxLines lines are kept (the
// newest); older ones are dropped and counted in first_index().
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace capflow::serve {

class AppendedLines {
 public:
  static constexpr size_t kMaxLines = 200000;
  static constexpr size_t kMaxFileBytes = size_t(1) << 30;

  AppendedLines(std::string path, std::string what) : path_(std::move(path)), what_(std::move(what)) {}

  // Reads what was appended; false when the file cannot be read now (missing: no lines).
  bool refresh();
  const std::vector<std::string>& lines() const { return lines_; }
  // The index (from the file's first line) of lines()[0].
  size_t first_index() const { return dropped_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_, what_;
  std::vector<std::string> lines_;
  std::string partial_;
  size_t offset_ = 0, dropped_ = 0;
  unsigned long long inode_ = 0;
};

}  // namespace capflow::serve
