// Checkpoint container: exact round trip, atomic write, clear refusal of bad files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <limits>

#include "output/checkpoint.h"

using capflow::output::Checkpoint;
using capflow::output::CheckpointError;
namespace fs = std::filesystem;

namespace {
fs::path tmpdir() {
  const fs::path d = fs::temp_directory_path() / ("capflow_ckpt_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}
std::string message_of(const std::string& path) {
  try {
    Checkpoint::read(path);
  } catch (const CheckpointError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Checkpoint, RoundTripIsBitExact) {
  const fs::path p = tmpdir() / "a.ckpt";
  Checkpoint c;
  std::vector<double> x = {1.0 / 3.0, -0.0, 1e-310, std::numeric_limits<double>::max(), M_PI};
  c.put("x", x);
  c.put("steps", std::vector<int64_t>{42, -7});
  c.put("law", std::string("skalak"));
  c.put_scalar("t", 0.1 + 0.2);
  c.write(p.string());
  EXPECT_FALSE(fs::exists(p.string() + ".tmp"));
  const Checkpoint r = Checkpoint::read(p.string());
  const auto& y = r.doubles("x", 5);
  for (size_t i = 0; i < x.size(); ++i)
    EXPECT_EQ(std::memcmp(&x[i], &y[i], sizeof(double)), 0) << i;
  EXPECT_EQ(r.ints("steps")[1], -7);
  EXPECT_EQ(r.text("law"), "skalak");
  EXPECT_EQ(r.scalar("t"), 0.1 + 0.2);
}

TEST(Checkpoint, MissingFieldAndWrongSizeAreNamed) {
  const fs::path p = tmpdir() / "b.ckpt";
  Checkpoint c;
  c.put("x", std::vector<double>{1, 2, 3});
  c.write(p.string());
  const Checkpoint r = Checkpoint::read(p.string());
  try {
    r.doubles("y");
    FAIL();
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("no field \"y\""), std::string::npos);
  }
  try {
    r.doubles("x", 4);
    FAIL();
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("expected 4"), std::string::npos);
  }
}

TEST(Checkpoint, RefusesForeignTruncatedAndCorruptFiles) {
  const fs::path d = tmpdir();
  {
    std::ofstream f(d / "foreign.ckpt");
    f << "{\"not\": \"a checkpoint\"}";
  }
  EXPECT_NE(message_of((d / "foreign.ckpt").string()).find("not a capflow checkpoint"), std::string::npos);
  EXPECT_NE(message_of((d / "missing.ckpt").string()).find("cannot open"), std::string::npos);

  Checkpoint c;
  c.put("x", std::vector<double>(100, 1.5));
  c.write((d / "good.ckpt").string());
  std::string bytes;
  {
    std::ifstream f(d / "good.ckpt", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), {});
  }
  {  // truncated
    std::ofstream f(d / "trunc.ckpt", std::ios::binary);
    f.write(bytes.data(), bytes.size() / 2);
  }
  EXPECT_NE(message_of((d / "trunc.ckpt").string()).find("truncated"), std::string::npos);
  {  // one flipped bit in the payload
    std::string b = bytes;
    b[60] ^= 0x10;
    std::ofstream f(d / "flip.ckpt", std::ios::binary);
    f.write(b.data(), b.size());
  }
  EXPECT_NE(message_of((d / "flip.ckpt").string()).find("checksum"), std::string::npos);
  {  // another format version
    std::string b = bytes;
    b[8] = 9;
    std::ofstream f(d / "ver.ckpt", std::ios::binary);
    f.write(b.data(), b.size());
  }
  EXPECT_NE(message_of((d / "ver.ckpt").string()).find("format version 9"), std::string::npos);
  fs::remove_all(d);
}
