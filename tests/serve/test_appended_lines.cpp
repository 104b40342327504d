// serve/appended_lines: a file read incrementally as a run appends to it, cut back by a resume, or
// replaced; never blocking on a FIFO.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "serve/appended_lines.h"

namespace capflow::serve {
namespace {

TEST(AppendedLines, ReadsWholeLinesAsTheyArrive) {
  const std::string path = std::filesystem::temp_directory_path() /
                           ("capflow_lines_" + std::to_string(::getpid()));
  std::filesystem::remove(path);
  AppendedLines l(path, "test file");
  EXPECT_FALSE(l.refresh());
  { std::ofstream(path) << "a\nb\npart"; }
  EXPECT_TRUE(l.refresh());
  EXPECT_EQ(l.lines(), (std::vector<std::string>{"a", "b"}));
  { std::ofstream(path, std::ios::app) << "ial\nc\n"; }
  EXPECT_TRUE(l.refresh());
  EXPECT_EQ(l.lines(), (std::vector<std::string>{"a", "b", "partial", "c"}));
  std::filesystem::resize_file(path, 2);  // a resume cut it back
  EXPECT_TRUE(l.refresh());
  EXPECT_EQ(l.lines(), (std::vector<std::string>{"a"}));
  std::filesystem::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  EXPECT_FALSE(l.refresh()) << "a FIFO is refused, not read";
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace capflow::serve
