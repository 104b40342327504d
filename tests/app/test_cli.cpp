// The capflow executable's command line as a whole: --version, and an unknown command named with
// the list of commands (exit 2).
#include <gtest/gtest.h>

#include <string>

#include "process_util.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace capflow;

TEST(Cli, VersionAndUnknownCommands) {
  const fs::path d = test::fresh_dir("cli");
  // --version prints to stdout, which spawn discards: the exit code only; the text through sh
  EXPECT_EQ(test::run_capflow({CAPFLOW_EXE, "--version"}, d / "log1"), 0);
  EXPECT_EQ(
      test::run_capflow({"/bin/sh", "-c", std::string(CAPFLOW_EXE) + " --version >&2"}, d / "log2"),
      0);
  const std::string version = test::read_file(d / "log2");
  EXPECT_EQ(version.rfind(std::string("capflow ") + CAPFLOW_VERSION + "\nbuilt with -", 0), 0u)
      << version;
  EXPECT_EQ(test::run_capflow({CAPFLOW_EXE, "rn", "x.json"}, d / "log3"), 2);
  const std::string err = test::read_file(d / "log3");
  EXPECT_NE(err.find("unknown command 'rn'"), std::string::npos) << err;
  EXPECT_NE(err.find("run, steady, sweep"), std::string::npos) << err;
  fs::remove_all(d);
}
