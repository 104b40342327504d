#include "serve/appended_lines.h"

#include <sys/stat.h>
#include <unistd.h>

#include "files/input_file.h"

namespace capflow::serve {

bool AppendedLines::refresh() {
  try {
    files::InputFile f(path_, what_, kMaxFileBytes);
    struct stat st {};
    if (fstat(f.fd(), &st) != 0) return false;
    const unsigned long long inode = static_cast<unsigned long long>(st.st_ino);
    if (inode != inode_ || f.size() < offset_) {
      lines_.clear();
      partial_.clear();
      offset_ = dropped_ = 0;
      inode_ = inode;
    }
    std::string added;
    added.resize(f.size() - offset_);
    size_t got = 0;
    while (got < added.size()) {
      const ssize_t n = pread(f.fd(), added.data() + got, added.size() - got,
                              static_cast<off_t>(offset_ + got));
      if (n <= 0) break;
      got += static_cast<size_t>(n);
    }
    added.resize(got);
    offset_ += got;
    partial_ += added;
    size_t start = 0;
    for (size_t nl; (nl = partial_.find('\n', start)) != std::string::npos; start = nl + 1)
      lines_.push_back(partial_.substr(start, nl - start));
    partial_.erase(0, start);
    if (lines_.size() > kMaxLines) {
      const size_t drop = lines_.size() - kMaxLines;
      lines_.erase(lines_.begin(), lines_.begin() + static_cast<long>(drop));
      dropped_ += drop;
    }
    return true;
  } catch (const files::InputError&) {
    return false;
  }
}

}  // namespace capflow::serve
