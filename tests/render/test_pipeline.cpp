// The renderer thread end to end: producer -> queue -> render -> PNG + MP4. Every movie frame
// arrives (back-pressure, no drops), previews never block, stop() finalises the movie.
// This is the test scripts/tsan-render runs under ThreadSanitizer.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <atomic>
#include <functional>
#include <mutex>
#include <vector>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "../output/ffprobe_util.h"
#include "render/render_thread.h"
#include "render_test_util.h"

namespace capflow::render {
namespace {

std::string temp_dir(const char* name) {
  const std::string d =
      std::string(::testing::TempDir()) + "capflow_" + std::to_string(::getpid()) + "_" + name;
  std::system(("rm -rf '" + d + "' && mkdir -p '" + d + "'").c_str());
  return d;
}

RenderOptions pipeline_options(const std::string& dir) {
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.msaa = 0;
  o.png = true;
  o.png_dir = dir + "/frames";
  o.mp4 = true;
  o.mp4_path = dir + "/movie.mp4";
  o.fps = 10;
  o.preview = true;
  o.preview_path = dir + "/preview.png";
  o.queue_capacity = 2;
  return o;
}

Snapshot frame_snapshot(int k) {
  const double a = 1.0 + 0.05 * k;
  Snapshot s = testing::shape_snapshot(6, 6, geometry::ellipsoid_map(a, 1.0 / std::sqrt(a), 1.0),
                                       [](double x, double, double) { return x; });
  s.time = 0.1 * k;
  s.frame = k;
  return s;
}

// The busy signals a RenderThread sends (its on_busy callback), recorded in order.
struct BusyLog {
  std::mutex mu;
  std::vector<bool> events;
  // idle_delay: how long a "false" call takes before it is recorded (a slow callback)
  std::function<void(bool)> callback(std::chrono::microseconds idle_delay = {}) {
    return [this, idle_delay](bool busy) {
      if (!busy) std::this_thread::sleep_for(idle_delay);
      std::lock_guard<std::mutex> l(mu);
      events.push_back(busy);
    };
  }
};

TEST(Pipeline, EveryMovieFrameIsRenderedAndEncoded) {
  const std::string dir = temp_dir("pipeline");
  RenderThread rt;
  std::string log;
  rt.start(pipeline_options(dir), [&log](const std::string& m) { log += m + "\n"; });
  EXPECT_NE(rt.context_info().renderer, "");
  const int frames = 15;
  for (int k = 0; k < frames; ++k) {
    ASSERT_TRUE(rt.submit_frame(frame_snapshot(k)));  // may block: back-pressure
    for (int p = 0; p < 3; ++p) {
      const auto t0 = std::chrono::steady_clock::now();
      rt.offer_preview(frame_snapshot(k));
      EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(200));
    }
  }
  const RenderStats st = rt.stop();
  EXPECT_EQ(rt.error(), "");
  EXPECT_EQ(st.movie_frames, frames);
  EXPECT_GT(st.producer_waits, 0);                   // the renderer was slower than the producer
  EXPECT_FALSE(rt.submit_frame(frame_snapshot(0)));  // after stop
  EXPECT_NE(log.find("render: backend"), std::string::npos) << log;
  const auto r = capflow::testing::ffprobe(dir + "/movie.mp4");
  ASSERT_TRUE(r.ok) << r.raw;
  EXPECT_EQ(r.codec, "h264");
  EXPECT_EQ(r.pix_fmt, "yuv420p");
  EXPECT_EQ(r.packets, frames);
  EXPECT_NEAR(r.duration, frames / 10.0, 1e-3);
  for (int k = 0; k < frames; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "/frames/frame_%06d.png", k);
    EXPECT_TRUE(std::ifstream(dir + name).good()) << name;
  }
  EXPECT_TRUE(std::ifstream(dir + "/preview.png").good());
}

// The busy signal of the CPU budget (app/cpu_budget.h): true while the renderer sets up and when
// a frame goes to an idle renderer, false when the last frame is written; busy() agrees, and it
// ends false.
TEST(Pipeline, BusySignalBracketsTheFramesInFlight) {
  const std::string dir = temp_dir("busy");
  RenderThread rt;
  BusyLog log;
  rt.start(pipeline_options(dir), nullptr, log.callback());
  EXPECT_FALSE(rt.busy());
  for (int k = 0; k < 6; ++k) {
    ASSERT_TRUE(rt.submit_frame(frame_snapshot(k)));
    EXPECT_TRUE(rt.busy() || k > 0);  // the first frame cannot be written before we look
  }
  const RenderStats st = rt.stop();
  EXPECT_EQ(st.movie_frames, 6);
  EXPECT_FALSE(rt.busy());
  std::lock_guard<std::mutex> l(log.mu);
  const std::vector<bool>& events = log.events;
  ASSERT_GE(events.size(), 2u);
  EXPECT_TRUE(events.front());
  EXPECT_FALSE(events.back());
  for (size_t k = 1; k < events.size(); ++k) EXPECT_NE(events[k], events[k - 1]) << k;
}

// A frame submitted the moment the renderer went idle races with the report of that idleness
// (the renderer thread's "false" against this thread's "true"; the callback's "false" is made
// slow to widen the race): the signal still alternates and ends in the present state, for
// frames resubmitted as soon as busy() turns false.
TEST(Pipeline, BusySignalKeepsItsOrderWhenASubmitRacesTheLastFrame) {
  const std::string dir = temp_dir("busy_race");
  RenderOptions o = pipeline_options(dir);
  o.width = 64;
  o.height = 48;
  o.png = false;
  o.preview = false;
  RenderThread rt;
  BusyLog log;
  rt.start(o, nullptr, log.callback(std::chrono::microseconds(300)));
  const int frames = 60;
  for (int k = 0; k < frames; ++k) {
    while (rt.busy()) {
    }
    ASSERT_TRUE(rt.submit_frame(frame_snapshot(k)));
  }
  EXPECT_EQ(rt.stop().movie_frames, frames);
  std::lock_guard<std::mutex> l(log.mu);
  const std::vector<bool>& events = log.events;
  ASSERT_GE(events.size(), 2u);
  EXPECT_FALSE(events.back());
  for (size_t k = 1; k < events.size(); ++k) ASSERT_NE(events[k], events[k - 1]) << k;
}

// launch(): the set-up (context, shaders, writers) runs in the renderer thread while the caller
// goes on and counts as busy; frames submitted before it is ready are all written.
TEST(Pipeline, LaunchedRendererTakesFramesWhileItSetsUp) {
  const std::string dir = temp_dir("launch");
  RenderThread rt;
  BusyLog log;
  rt.launch(pipeline_options(dir), nullptr, log.callback());
  {
    std::lock_guard<std::mutex> l(log.mu);
    ASSERT_EQ(log.events.size(), 1u);  // signalled before launch() returns
    EXPECT_TRUE(log.events.front());
  }
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(rt.submit_frame(frame_snapshot(k)));
  rt.wait_ready();
  const RenderStats st = rt.stop();
  EXPECT_EQ(st.movie_frames, 4);
  EXPECT_TRUE(rt.error().empty()) << rt.error();
  EXPECT_FALSE(rt.busy());
  std::lock_guard<std::mutex> l(log.mu);
  EXPECT_FALSE(log.events.back());
  const auto r = capflow::testing::ffprobe(dir + "/movie.mp4");
  ASSERT_TRUE(r.ok) << r.raw;
  EXPECT_EQ(r.packets, 4);
}

// A set-up that fails in the background (here: the movie's directory does not exist) reaches
// the producer: wait_ready() rethrows, submit_frame() returns false, error() says why, and the
// busy signal ends false.
TEST(Pipeline, BackgroundSetUpFailureReachesTheProducer) {
  const std::string dir = temp_dir("launch_fail");
  RenderOptions o = pipeline_options(dir);
  o.mp4_path = dir + "/missing/movie.mp4";
  RenderThread rt;
  std::atomic<bool> last{true};
  rt.launch(o, nullptr, [&](bool busy) { last = busy; });
  rt.submit_frame(frame_snapshot(0));  // may be taken (queued) or refused: the set-up races
  EXPECT_THROW(rt.wait_ready(), std::exception);
  EXPECT_FALSE(rt.submit_frame(frame_snapshot(1)));
  EXPECT_NE(rt.error().find("cannot start the renderer"), std::string::npos) << rt.error();
  EXPECT_FALSE(rt.busy());
  EXPECT_FALSE(last.load());
  EXPECT_EQ(rt.stop().movie_frames, 0);
}

TEST(Pipeline, SignalledRunEndsWithFinalisedMovie) {
  const std::string dir = temp_dir("signal");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    install_stop_signal_handlers();
    RenderThread rt;
    RenderOptions o = pipeline_options(dir);
    o.png = false;
    o.flush_every = 1000;  // only the clean finish writes the frames out
    rt.start(o);
    long k = 0;
    while (!stop_requested() && k < 10000)
      rt.submit_frame(frame_snapshot(static_cast<int>(k++ % 20)));
    const RenderStats st = rt.stop();
    std::ofstream(dir + "/count") << st.movie_frames;
    _exit(rt.error().empty() ? 0 : 1);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ::kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  long written = -1;
  std::ifstream(dir + "/count") >> written;
  ASSERT_GT(written, 0);
  const auto r = capflow::testing::ffprobe(dir + "/movie.mp4");
  ASSERT_TRUE(r.ok) << r.raw;
  EXPECT_EQ(r.packets, written);
  EXPECT_NEAR(r.duration, written / 10.0, 1e-3);
}

}  // namespace
}  // namespace capflow::render
