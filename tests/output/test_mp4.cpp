// MP4 writer: ffprobe sees h264/yuv420p with exactly the submitted frames and
// duration = frames/fps; a process killed with SIGKILL mid-recording leaves a file that
// opens and holds the frames written before the last fragment flush.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <vector>

#include "ffprobe_util.h"
#include "output/mp4_writer.h"

namespace capflow::output {
namespace {

std::vector<uint8_t> pattern(int w, int h, int k) {
  std::vector<uint8_t> img(static_cast<size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &img[(static_cast<size_t>(y) * w + x) * 4];
      p[0] = static_cast<uint8_t>(x + 3 * k);
      p[1] = static_cast<uint8_t>(y + 5 * k);
      p[2] = static_cast<uint8_t>(128 + 64 * ((x / 16 + y / 16 + k) % 2));
      p[3] = 255;
    }
  return img;
}

std::string temp_path(const char* name) {
  return std::string(::testing::TempDir()) + "capflow_" + std::to_string(::getpid()) + "_" + name;
}

TEST(Mp4Writer, ProbeShowsH264Yuv420pFrameCountAndDuration) {
  const std::string path = temp_path("probe.mp4");
  Mp4Options o;
  o.width = 320;
  o.height = 240;
  o.fps = 24;
  o.flush_every = 5;
  {
    Mp4Writer w(path, o);
    for (int k = 0; k < 36; ++k) w.add_frame(pattern(o.width, o.height, k).data());
    w.finish();
    EXPECT_EQ(w.frames(), 36);
  }
  const auto r = capflow::testing::ffprobe(path);
  ASSERT_TRUE(r.ok) << r.raw;
  EXPECT_EQ(r.codec, "h264");
  EXPECT_EQ(r.pix_fmt, "yuv420p");
  EXPECT_EQ(r.width, 320);
  EXPECT_EQ(r.height, 240);
  EXPECT_EQ(r.packets, 36);
  EXPECT_NEAR(r.duration, 36.0 / 24.0, 1e-3) << r.raw;
  std::remove(path.c_str());
}

TEST(Mp4Writer, RejectsOddSize) {
  Mp4Options o;
  o.width = 321;
  o.height = 240;
  EXPECT_THROW(Mp4Writer(temp_path("odd.mp4"), o), std::invalid_argument);
}

TEST(Mp4Writer, SurvivesKill9WithFramesBeforeLastFlush) {
  const std::string path = temp_path("killed.mp4");
  const int flushed = 20;
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    Mp4Options o;
    o.width = 256;
    o.height = 144;
    o.fps = 30;
    o.flush_every = 1000;  // only explicit flushes
    Mp4Writer w(path, o);
    for (int k = 0; k < flushed; ++k) w.add_frame(pattern(o.width, o.height, k).data());
    w.flush();
    for (int k = 0; k < 7; ++k) w.add_frame(pattern(o.width, o.height, k).data());  // unflushed
    std::raise(SIGKILL);  // kill -9 mid-recording: no trailer, no destructor
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  const auto r = capflow::testing::ffprobe(path);
  ASSERT_TRUE(r.ok) << "killed file does not open: " << r.raw;
  EXPECT_EQ(r.codec, "h264");
  EXPECT_EQ(r.packets, flushed) << r.raw;
  std::remove(path.c_str());
}

}  // namespace
}  // namespace capflow::output
