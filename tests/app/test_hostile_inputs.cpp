// The second hostile-input round (Milestone 17), inputs: every file capflow reads follows one rule
// (a regular file of bounded size, checked before it is read), every number is bounded where it
// enters, and every user error exits 2 naming what is wrong - for run, steady, sweep, render and
// figure alike. Each case failed before its fix (the issue lists what it did then).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "hostile_util.h"
#include "output/checkpoint.h"

using namespace capflow;
using test::contains;
using test::outcome;
namespace fs = std::filesystem;

namespace {

// A finished small run with three checkpoints (the last at its end).
fs::path finished_run(const fs::path& d, const std::string& name = "run") {
  const fs::path ctl = d / (name + ".json"), run = d / name;
  test::write_file(ctl, test::small_run(0.06, R"("checkpoint_every": 0.02)"));
  EXPECT_EQ(test::capflow({"run", ctl.string(), "-o", run.string()}, d / (name + ".log")), 0)
      << test::read_file(d / (name + ".log"));
  return run;
}

std::string newest_checkpoint(const fs::path& run) {
  std::vector<std::string> all;
  for (const auto& e : fs::directory_iterator(run / "checkpoints")) all.push_back(e.path());
  std::sort(all.begin(), all.end());
  return all.back();
}

}  // namespace

// --resume, start.from, render and figure each hung on a FIFO (or /dev/zero) where a checkpoint
// or a CSV was expected.
TEST(HostileInputs, SpecialFilesAreRefusedWithoutBlocking) {
  const fs::path d = test::fresh_dir("special");
  const fs::path run = finished_run(d);
  // --resume: the newest checkpoint a FIFO - skipped (named), the one before continues
  const fs::path resumed = d / "resumed";
  fs::copy(run, resumed, fs::copy_options::recursive);
  fs::remove(resumed / "run.lock");
  ASSERT_EQ(::mkfifo((resumed / "checkpoints" / "ckpt_9999999999.ckpt").c_str(), 0644), 0);
  auto o = outcome({"run", "--resume", resumed.string(), "--t-end", "0.08"}, d);
  EXPECT_EQ(o.code, 0) << o.log;
  EXPECT_TRUE(contains(o.log, "is a FIFO: a checkpoint must be a regular file")) << o.log;
  // start.from: a run whose only checkpoint is a FIFO, or a symlink to /dev/zero
  for (const char* kind : {"fifo", "zero"}) {
    const fs::path src = d / (std::string("src_") + kind);
    fs::create_directories(src / "checkpoints");
    fs::copy_file(run / "control.json", src / "control.json");
    fs::copy_file(run / "events.jsonl", src / "events.jsonl");
    const fs::path ck = src / "checkpoints" / "ckpt_0000000001.ckpt";
    if (std::string(kind) == "fifo")
      ASSERT_EQ(::mkfifo(ck.c_str(), 0644), 0);
    else
      fs::create_symlink("/dev/zero", ck);
    test::write_file(d / "from.json", test::small_run(0.1, "", R"("start": {"from": ")" +
                                                                  src.string() + R"("})"));
    o = outcome({"run", (d / "from.json").string(), "-o", (d / "from_run").string()}, d);
    EXPECT_EQ(o.code, 2) << o.log;
    EXPECT_TRUE(contains(o.log, "start.from")) << o.log;
    EXPECT_FALSE(fs::exists(d / "from_run"));
    // render of that run directory
    o = outcome({"render", src.string(), "-o", (d / "x.png").string()}, d);
    EXPECT_EQ(o.code, 2) << o.log;
    EXPECT_TRUE(contains(o.log, "must be a regular file")) << o.log;
  }
  // figure: timeseries.csv a FIFO (the run is left out; nothing else to draw: exit 2)
  const fs::path fifo_run = d / "fifo_run";
  fs::copy(run, fifo_run, fs::copy_options::recursive);
  fs::remove(fifo_run / "timeseries.csv");
  ASSERT_EQ(::mkfifo((fifo_run / "timeseries.csv").c_str(), 0644), 0);
  o = outcome({"figure", fifo_run.string(), "-o", (d / "figs").string(), "--kinds", "timeseries",
               "--no-gnuplot"},
              d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "timeseries.csv: is a FIFO")) << o.log;
  // --resume with a record file replaced by a FIFO
  fs::remove(resumed / "events.jsonl");
  ASSERT_EQ(::mkfifo((resumed / "events.jsonl").c_str(), 0644), 0);
  o = outcome({"run", "--resume", resumed.string(), "--t-end", "0.1"}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "events.jsonl is a FIFO")) << o.log;
  fs::remove_all(d);
}

// A sparse 2 GiB .ckpt or .vtp was read whole (4.1 GiB resident, 20 s) before its magic bytes
// were checked.
TEST(HostileInputs, FilesAreCheckedBeforeTheirBodiesAreRead) {
  const fs::path d = test::fresh_dir("sparse");
  for (const char* name : {"big.ckpt", "big.vtp"}) {
    { std::ofstream f(d / name); }
    fs::resize_file(d / name, std::uintmax_t{2} << 30);
    const auto o = outcome({"render", (d / name).string(), "-o", (d / "x.png").string()}, d);
    EXPECT_EQ(o.code, 2) << o.log;
    EXPECT_TRUE(contains(o.log, "is 2 GiB, larger than")) << o.log;
  }
  // within the bound, a foreign header is refused from its first bytes
  { std::ofstream(d / "foreign.ckpt") << "NOTCAPFLOW........................"; }
  fs::resize_file(d / "foreign.ckpt", std::uintmax_t{60} << 20);
  auto o = outcome({"render", (d / "foreign.ckpt").string(), "-o", (d / "x.png").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "not a capflow checkpoint (wrong magic bytes)")) << o.log;
  { std::ofstream(d / "foreign.vtp") << "PK\x03\x04 a zip file"; }
  o = outcome({"render", (d / "foreign.vtp").string(), "-o", (d / "x.png").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "not a ParaView surface")) << o.log;
  EXPECT_FALSE(fs::exists(d / "x.png"));
  fs::remove_all(d);
}

// Extreme numbers: bad_alloc (exit 3), a renderer killed, runs that never end.
TEST(HostileInputs, NumbersAreBoundedWhereTheyEnter) {
  const fs::path d = test::fresh_dir("numbers");
  // capflow steady: {"steps": {"to": 100, "by": 1e-9}}
  test::write_file(d / "steps.json",
                   R"({"mesh": {"elements": 6, "nb": 6}, "ca": [{"steps": {"to": 100, "by": 1e-9}}]})");
  auto o = outcome({"steady", (d / "steps.json").string(), "-o", (d / "s").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "ca[0].steps.by: value 1e-09 makes 1e+11 levels")) << o.log;
  // render / figure --range that double precision cannot resolve, or overflows
  for (const char* range : {"1e16,10000000000000002", "-1e308,1e308"}) {
    o = outcome({"render", "--range", range, "-o", (d / "x.png").string()}, d);
    EXPECT_EQ(o.code, 2) << range << o.log;
    EXPECT_TRUE(contains(o.log, "--range [")) << o.log;
  }
  const fs::path run = finished_run(d);
  o = outcome({"figure", run.string(), "-o", (d / "f").string(), "--kinds", "views", "--range",
               "1e16,10000000000000002"},
              d);
  EXPECT_EQ(o.code, 2) << o.log;
  // render.range in a run's control file
  for (const char* range : {"[1e16, 10000000000000002]", "[-1e308, 1e308]"}) {
    test::write_file(d / "r.json", test::small_run(0.04, R"("frame_every": 0.02)",
                                                   std::string(R"("render": {"range": )") + range +
                                                       "}"));
    o = outcome({"run", (d / "r.json").string(), "-o", (d / "rr").string()}, d);
    EXPECT_EQ(o.code, 2) << o.log;
    EXPECT_TRUE(contains(o.log, "render.range")) << o.log;
    EXPECT_FALSE(fs::exists(d / "rr"));
  }
  // a sweep range from -1e308 to 1e308 (an infinite middle value: exit 3 before)
  test::write_file(d / "sw.json", R"({"base": {"ca": 0.3, "mesh": {"elements": 6, "nb": 6}},
      "vary": {"ca": {"from": -1e308, "to": 1e308, "count": 3}}, "output": {"dir": ")" +
                                      (d / "sw").string() + R"("}})");
  o = outcome({"sweep", (d / "sw.json").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "case 2 (ca = 1e+308)")) << o.log;
  fs::remove_all(d);
}

// render --eye nan,0,0, --fov nan and degenerate --ellipsoid axes wrote an image (exit 0).
TEST(HostileInputs, RenderOptionsAreChecked) {
  const fs::path d = test::fresh_dir("options");
  const fs::path png = d / "x.png";
  const std::vector<std::vector<std::string>> bad = {
      {"--eye", "nan,0,0"},          {"--eye", "0,0,0", "--target", "0,0,0"},
      {"--fov", "nan"},              {"--fov", "170"},
      {"--ellipsoid", "0,0,0"},      {"--ellipsoid", "-1,1,1"},
      {"--ellipsoid", "nan,1,1"},    {"--ellipsoid", "1e300,1,1"},
      {"--width", "100000"},         {"--height", "7"},
      {"--up", "0,0,1", "--eye", "0,0,6"}};
  for (const auto& args : bad) {
    std::vector<std::string> a = {"render", "-o", png.string()};
    a.insert(a.end(), args.begin(), args.end());
    const auto o = outcome(a, d);
    EXPECT_EQ(o.code, 2) << args[0] << " " << args[1] << o.log;
    EXPECT_TRUE(contains(o.log, args[0]) || contains(o.log, "--eye/--target/--up")) << o.log;
    EXPECT_FALSE(fs::exists(png)) << args[0] << " " << args[1];
  }
  fs::remove_all(d);
}

// Exit 3 means a bug in capflow; these were user errors reported as one.
TEST(HostileInputs, UserErrorsExitTwo) {
  const fs::path d = test::fresh_dir("classes");
  const fs::path run = finished_run(d);
  // figure -o onto an existing file, or where no directory can be made
  test::write_file(d / "file", "x");
  auto o = outcome({"figure", run.string(), "-o", (d / "file").string(), "--no-gnuplot"}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "exists and is not a directory")) << o.log;
  o = outcome({"figure", run.string(), "-o", "/proc/capflow_x", "--no-gnuplot"}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "/proc/capflow_x")) << o.log;
  // --vector bogus names the value
  o = outcome({"figure", run.string(), "-o", (d / "f").string(), "--vector", "bogus"}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "--vector bogus")) << o.log;
  // render of a checkpoint whose positions are all 0 or 1e300 (its CRC valid)
  for (double v : {0.0, 1e300}) {
    output::Checkpoint c = output::Checkpoint::read(newest_checkpoint(run));
    std::vector<double> x = c.doubles("x");
    std::fill(x.begin(), x.end(), v);
    c.put("x", x);
    const fs::path bad = d / "bad.ckpt";
    c.write(bad.string());
    o = outcome({"render", bad.string(), "-o", (d / "x.png").string()}, d);
    EXPECT_EQ(o.code, 2) << v << o.log;
    EXPECT_TRUE(contains(o.log, "bad.ckpt")) << o.log;
  }
  // start.from: "" created a run before
  test::write_file(d / "empty.json", test::small_run(0.04, "", R"("start": {"from": ""})"));
  o = outcome({"run", (d / "empty.json").string(), "-o", (d / "e").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_FALSE(fs::exists(d / "e"));
  fs::remove_all(d);
}

// Bytes from a .vtp (and from a control file's key) were echoed raw: an ESC sequence could
// retitle or clear the terminal. Messages name the file and the array.
TEST(HostileInputs, BytesFromFilesAreEscapedAndMessagesNameTheFile) {
  const fs::path d = test::fresh_dir("escape");
  const std::string name = "evil\x1b]0;PWNED\x07";
  test::write_file(d / "s.vtp",
                   "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" "
                   "byte_order=\"LittleEndian\" header_type=\"UInt64\"><PolyData><Piece "
                   "NumberOfPoints=\"1\" NumberOfPolys=\"0\"><PointData><DataArray "
                   "type=\"Float64\" Name=\"" +
                       name + "\" format=\"binary\">AAAA!!!!</DataArray></PointData></Piece>"
                              "</PolyData></VTKFile>\n");
  auto o = outcome({"render", (d / "s.vtp").string(), "-o", (d / "x.png").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_EQ(o.log.find('\x1b'), std::string::npos) << "raw ESC on the console";
  EXPECT_EQ(o.log.find('\x07'), std::string::npos) << "raw BEL on the console";
  EXPECT_TRUE(contains(o.log, "s.vtp: array evil\\x1B]0;PWNED\\x07: base64: invalid character "
                              "'!'"))
      << o.log;
  // a byte count beyond the data (vector::_M_default_append before)
  test::write_file(d / "n.vtp",
                   "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" "
                   "byte_order=\"LittleEndian\" header_type=\"UInt64\"><PolyData><Piece "
                   "NumberOfPoints=\"1\"><Points><DataArray type=\"Float64\" "
                   "NumberOfComponents=\"3\" format=\"binary\">//////////8=</DataArray></Points>"
                   "</Piece></PolyData></VTKFile>\n");
  o = outcome({"render", (d / "n.vtp").string(), "-o", (d / "x.png").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_TRUE(contains(o.log, "n.vtp: array (unnamed): byte count")) << o.log;
  // a control file key with an escape in it
  test::write_file(d / "k.json", "{\"ca\": 0.3, \"\\u001b[2J\": 1}");
  o = outcome({"run", (d / "k.json").string(), "-o", (d / "k").string()}, d);
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_EQ(o.log.find('\x1b'), std::string::npos) << o.log;
  EXPECT_TRUE(contains(o.log, "\\x1B[2J: unknown key")) << o.log;
  fs::remove_all(d);
}
