// files/atomic_write: a failed write leaves the old file as it was and no temporary file; the
// error names the file and the cause.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "files/atomic_write.h"

namespace fs = std::filesystem;
using capflow::files::write_atomically;
using capflow::files::WriteError;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST(AtomicWrite, ReplacesTheFileWhole) {
  const fs::path d = fs::temp_directory_path() / ("capflow_aw_" + std::to_string(::getpid()));
  fs::create_directories(d);
  write_atomically((d / "f").string(), "first");
  write_atomically((d / "f").string(), "second");
  EXPECT_EQ(slurp(d / "f"), "second");
  write_atomically((d / "g").string(), "x", {true, true});
  EXPECT_EQ(slurp(d / "g"), "x");
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  fs::remove_all(d);
}

TEST(AtomicWrite, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path d = fs::temp_directory_path() / ("capflow_aw2_" + std::to_string(::getpid()));
  fs::create_directories(d);
  write_atomically((d / "f").string(), "old");
  // A file-size limit makes the write fail as a full disk does (in a child: the limit is
  // process-wide).
  const pid_t pid = fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit r {1000, 1000};
    setrlimit(RLIMIT_FSIZE, &r);
    try {
      write_atomically((d / "f").string(), std::string(5000, 'n'));
    } catch (const WriteError& e) {
      const std::string m = e.what();
      _exit(m.find("cannot write " + (d / "f").string()) != std::string::npos &&
                    m.find("File too large") != std::string::npos
                ? 0
                : 2);
    }
    _exit(1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(slurp(d / "f"), "old");
  EXPECT_FALSE(fs::exists(d / "f.tmp"));
  // a directory that does not exist: named
  EXPECT_THROW(write_atomically((d / "no" / "f").string(), "x"), WriteError);
  fs::remove_all(d);
}
