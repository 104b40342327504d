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

// capflow render SOURCE: a run directory (newest checkpoint; with --time the surface nearest to
// it), a checkpoint, a .vtp; bad sources exit 2 with a message.
TEST(Cli, RenderDrawsASavedState) {
  const fs::path d = test::fresh_dir("cli_render");
  test::write_file(d / "c.json", R"({"capsule": {"law": "skalak"}, "mesh": {"elements": 6, "nb": 6},
    "flow": {"type": "planar-extension"}, "ca": 0.45, "time": {"t_end": 0.1},
    "output": {"dir": ")" + (d / "run").string() +
                                     R"(", "png": false, "mp4": false,
               "vtk_every": 0.05, "vtk_points": 9},
    "render": {"width": 320, "height": 240, "view": "xy"}})");
  ASSERT_EQ(test::run_capflow({CAPFLOW_EXE, "run", (d / "c.json").string()}, d / "run.log", 300), 0)
      << test::read_file(d / "run.log");
  const auto png_size = [](const fs::path& p) {  // width, height from the PNG header
    const std::string h = test::read_file(p).substr(0, 24);
    const auto be = [&](int o) {
      return (static_cast<unsigned char>(h[o]) << 24) |
             (static_cast<unsigned char>(h[o + 1]) << 16) |
             (static_cast<unsigned char>(h[o + 2]) << 8) | static_cast<unsigned char>(h[o + 3]);
    };
    return std::pair<long, long>(be(16), be(20));
  };
  const std::string run = (d / "run").string();
  std::string vtp, ckpt;
  for (const auto& e : fs::directory_iterator(d / "run" / "vtk")) vtp = e.path().string();
  for (const auto& e : fs::directory_iterator(d / "run" / "checkpoints")) ckpt = e.path().string();
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Case> cases = {
      {{run}, "checkpoint"},
      {{run, "--time", "0.05"}, "nearest to 0.05"},
      {{vtp}, "surface"},
      {{ckpt}, "checkpoint"},
  };
  int k = 0;
  for (const Case& c : cases) {
    const fs::path out = d / ("r" + std::to_string(k) + ".png"),
                   log = d / ("r" + std::to_string(k) + ".log");
    std::vector<std::string> args = {CAPFLOW_EXE, "render"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"-o", out.string(), "--width", "320", "--height", "240"});
    EXPECT_EQ(test::run_capflow(args, log, 120), 0) << test::read_file(log);
    EXPECT_NE(test::read_file(log).find(c.says), std::string::npos) << test::read_file(log);
    ASSERT_TRUE(fs::exists(out)) << c.args[0];
    EXPECT_EQ(png_size(out), (std::pair<long, long>(320, 240)));
    ++k;
  }
  EXPECT_EQ(test::run_capflow({CAPFLOW_EXE, "render", (d / "none").string()}, d / "bad1.log"), 2);
  EXPECT_NE(test::read_file(d / "bad1.log").find("no such file"), std::string::npos);
  EXPECT_EQ(test::run_capflow({CAPFLOW_EXE, "render", run, "--shape", "sphere"}, d / "bad2.log"),
            2);
  EXPECT_NE(test::read_file(d / "bad2.log").find("only without a SOURCE"), std::string::npos);
  EXPECT_EQ(test::run_capflow({CAPFLOW_EXE, "render", "--time", "1"}, d / "bad3.log"), 2);
  fs::remove_all(d);
}
