// files/input_file: the one rule for every file capflow reads. Special files are refused before a
// byte is read (a FIFO nobody writes to would block, /dev/zero never ends), the size is known
// and bounded before the body is read (a sparse 2 GiB file costs nothing), and a header can be
// checked first.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "files/input_file.h"

using capflow::files::InputError;
using capflow::files::InputFile;
using capflow::files::read_input_file;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("capflow_files_" + name + "_" +
                                                 std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The problem InputFile reports for a path ("" when it opens).
std::string problem(const fs::path& p, std::size_t max = 1 << 20) {
  try {
    InputFile f(p.string(), "test file", max);
    return "";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p.string());
    return e.problem();
  }
}

}  // namespace

TEST(InputFile, SpecialFilesAreRefusedWithoutBlocking) {
  const fs::path d = scratch("special");
  ASSERT_EQ(::mkfifo((d / "fifo").c_str(), 0644), 0);
  EXPECT_NE(problem(d / "fifo").find("is a FIFO: a test file must be a regular file"),
            std::string::npos);
  fs::create_symlink("/dev/zero", d / "zero");
  EXPECT_NE(problem(d / "zero").find("is a device"), std::string::npos);
  EXPECT_NE(problem(d).find("is a directory"), std::string::npos);
  EXPECT_NE(problem(d / "missing").find("cannot open the file: No such file"), std::string::npos);
  // a symlink to a regular file is followed
  std::ofstream(d / "real") << "abc";
  fs::create_symlink(d / "real", d / "link");
  EXPECT_EQ(read_input_file((d / "link").string(), "test file", 10), "abc");
  fs::remove_all(d);
}

TEST(InputFile, TheSizeIsBoundedBeforeTheBodyIsRead) {
  const fs::path d = scratch("size");
  {
    std::ofstream f(d / "sparse");
  }
  fs::resize_file(d / "sparse", std::uintmax_t{2} << 30);  // 2 GiB of holes
  // Refused from its size: the child reading it stays far below the file's size in memory.
  const pid_t pid = fork();
  if (pid == 0) {
    bool refused = false;
    try {
      read_input_file((d / "sparse").string(), "test file", 64 << 20);
    } catch (const InputError& e) {
      refused = std::string(e.problem()).find("is 2 GiB, larger than 64 MiB") != std::string::npos;
    }
    struct rusage ru {};
    getrusage(RUSAGE_SELF, &ru);
    _exit(refused && ru.ru_maxrss < 200 * 1024 ? 0 : 1);  // ru_maxrss in KiB
  }
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  // the bound is inclusive
  std::ofstream(d / "ten") << "0123456789";
  EXPECT_EQ(problem(d / "ten", 10), "");
  EXPECT_NE(problem(d / "ten", 9).find("is 10 bytes, larger than 9 bytes"), std::string::npos);
  fs::remove_all(d);
}

TEST(InputFile, TheHeaderIsReadFirst) {
  const fs::path d = scratch("header");
  std::ofstream(d / "f") << "MAGICand the body";
  InputFile f((d / "f").string(), "test file", 100);
  EXPECT_EQ(f.size(), 17u);
  EXPECT_EQ(f.read_prefix(5), "MAGIC");
  EXPECT_EQ(f.read_prefix(100), "MAGICand the body");
  EXPECT_EQ(f.read_all(), "MAGICand the body");
  fs::remove_all(d);
}

TEST(InputFile, AFileThatGrowsIsReadAsItWasWhenOpened) {
  const fs::path d = scratch("grow");
  std::ofstream(d / "f") << "row1\n";
  InputFile f((d / "f").string(), "test file", 100);
  std::ofstream(d / "f", std::ios::app) << "row2\n";
  EXPECT_EQ(f.read_all(), "row1\n");
  fs::remove_all(d);
}

TEST(InputFile, SizesReadAsPeopleWriteThem) {
  using capflow::files::size_text;
  EXPECT_EQ(size_text(812), "812 bytes");
  EXPECT_EQ(size_text(1 << 20), "1 MiB");
  EXPECT_EQ(size_text(std::size_t{2} << 30), "2 GiB");
  EXPECT_EQ(size_text((1 << 20) + 20), "1048596 bytes");
  EXPECT_EQ(size_text(std::size_t{300} << 20 | 7), "about 300 MiB");
}
