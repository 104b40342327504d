#include "render/render_thread.h"

#include <sys/stat.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <future>

#include "output/mp4_writer.h"
#include "output/png_writer.h"

namespace capflow::render {
namespace {
volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_stop_signal(int) {
  g_stop = 1;
}
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

void install_stop_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}
bool stop_requested() {
  return g_stop != 0;
}

RenderThread::~RenderThread() {
  stop();
}

void RenderThread::start(const RenderOptions& options, LogFn log,
                         std::function<void(bool)> on_busy) {
  launch(options, std::move(log), std::move(on_busy));
  wait_ready();
}

void RenderThread::launch(const RenderOptions& options, LogFn log,
                          std::function<void(bool)> on_busy) {
  if (thread_.joinable()) throw std::logic_error("RenderThread: already started");
  std::string err;
  if (!options.IsValid(&err)) throw std::invalid_argument("render options: " + err);
  opt_ = options;
  log_ = std::move(log);
  on_busy_ = std::move(on_busy);
  error_.clear();
  stats_ = RenderStats{};
  written_through_.store(-1, std::memory_order_relaxed);
  busy_reported_ = false;
  queue_ = std::make_unique<SnapshotQueue>(static_cast<size_t>(opt_.queue_capacity));
  std::promise<void> ready;
  ready_ = ready.get_future().share();
  // Making the context (loading the driver), the shaders and the writers is the renderer's
  // work like a frame: it counts as one in flight, so the solver leaves it a core meanwhile.
  frames_in_flight_.store(1, std::memory_order_relaxed);
  report_busy();
  thread_ = std::thread([this, p = std::move(ready)]() mutable { run(std::move(p)); });
}

void RenderThread::wait_ready() {
  if (!ready_.valid()) throw std::logic_error("RenderThread: not launched");
  try {
    ready_.get();
  } catch (...) {
    if (thread_.joinable()) thread_.join();
    throw;
  }
}

void RenderThread::frame_done() {
  // Never below 0: fail() zeroes the count while a producer's refused frame may still be
  // counted out here.
  int n = frames_in_flight_.load(std::memory_order_relaxed);
  while (n > 0 && !frames_in_flight_.compare_exchange_weak(n, n - 1, std::memory_order_relaxed)) {
  }
  if (n == 1) {
    report_busy();
    std::lock_guard<std::mutex> l(idle_mu_);
    idle_cv_.notify_all();
  }
}

void RenderThread::wait_idle() {
  std::unique_lock<std::mutex> l(idle_mu_);
  idle_cv_.wait(l, [&] { return frames_in_flight_.load(std::memory_order_relaxed) == 0; });
}

long RenderThread::frames_written_through() const {
  return written_through_.load(std::memory_order_relaxed);
}

void RenderThread::report_busy() {
  if (!on_busy_) return;
  std::lock_guard<std::mutex> l(busy_mu_);
  const bool busy = frames_in_flight_.load(std::memory_order_relaxed) > 0;
  if (busy == busy_reported_) return;
  busy_reported_ = busy;
  on_busy_(busy);
}

void RenderThread::run(std::promise<void> ready) {
  // The GL context, the writers and everything using them live in this thread only.
  std::unique_ptr<Renderer> renderer;
  std::unique_ptr<output::Mp4Writer> mp4;
  try {
    set_up(&renderer, &mp4);
  } catch (const std::exception& e) {
    fail(std::string("cannot start the renderer: ") + e.what());  // closes the queue: frames
                                                                  // submitted meanwhile fail
    ready.set_exception(std::current_exception());
    return;
  }
  frame_done();  // the set-up
  ready.set_value();
  serve(*renderer, mp4.get());
}

void RenderThread::set_up(std::unique_ptr<Renderer>* renderer,
                          std::unique_ptr<output::Mp4Writer>* mp4) {
  *renderer = std::make_unique<Renderer>(opt_);
  const Renderer& r = **renderer;
  {
    std::lock_guard<std::mutex> l(mu_);
    info_ = r.context_info();
  }
  if (log_) {
    std::string aa = std::string("; anti-aliasing ") + antialias_name(r.antialias());
    if (r.antialias() == Antialias::Multisample) aa += " (" + std::to_string(r.msaa()) + "x)";
    log_(r.context_info().summary() + aa);
    for (const std::string& w : r.warnings()) log_("warning: " + w);
  }
  if (opt_.png) ::mkdir(opt_.png_dir.c_str(), 0777);
  if (opt_.mp4) {
    output::Mp4Options mo;
    mo.width = opt_.width;
    mo.height = opt_.height;
    mo.fps = opt_.fps;
    mo.crf = opt_.crf;
    mo.preset = opt_.preset;
    mo.flush_every = opt_.flush_every;
    *mp4 = std::make_unique<output::Mp4Writer>(opt_.mp4_path, mo);
  }
}

void RenderThread::serve(Renderer& renderer, output::Mp4Writer* mp4) {
  Image img;
  try {
    while (auto item = queue_->pop()) {
      FrameTimings t;
      renderer.render(item->snapshot, &img, &t);
      if (item->lane == SnapshotQueue::Lane::Preview) {
        if (opt_.preview)
          output::write_png(opt_.preview_path, img.width, img.height, img.rgba.data());
        std::lock_guard<std::mutex> l(mu_);
        ++stats_.previews;
        continue;
      }
      double png_ms = 0, enc_ms = 0;
      if (opt_.png) {
        auto t0 = std::chrono::steady_clock::now();
        char name[64];
        std::snprintf(name, sizeof name, "/frame_%06ld.png",
                      static_cast<long>(item->snapshot.frame));
        output::write_png(opt_.png_dir + name, img.width, img.height, img.rgba.data());
        png_ms = ms_since(t0);
      }
      if (mp4) {
        auto t0 = std::chrono::steady_clock::now();
        mp4->add_frame(img.rgba.data());
        enc_ms = ms_since(t0);
      }
      if (opt_.preview)
        output::write_png(opt_.preview_path, img.width, img.height, img.rgba.data());
      written_through_.store(item->snapshot.frame + 1, std::memory_order_relaxed);
      frame_done();
      std::lock_guard<std::mutex> l(mu_);
      ++stats_.movie_frames;
      stats_.total.upsample_ms += t.upsample_ms;
      stats_.total.draw_ms += t.draw_ms;
      stats_.total.overlay_ms += t.overlay_ms;
      stats_.total.readback_ms += t.readback_ms;
      stats_.png_ms += png_ms;
      stats_.encode_ms += enc_ms;
    }
    if (mp4) mp4->finish();
  } catch (const std::exception& e) {
    fail(e.what());
    try {
      if (mp4) mp4->finish();
    } catch (...) {
    }
  }
}

void RenderThread::fail(const std::string& msg) {
  {
    std::lock_guard<std::mutex> l(mu_);
    error_ = msg;
  }
  if (log_) log_("render: error: " + msg);
  queue_->close();  // producers stop blocking and see false
  if (frames_in_flight_.exchange(0) > 0) report_busy();
  std::lock_guard<std::mutex> l(idle_mu_);
  idle_cv_.notify_all();
}

bool RenderThread::submit_frame(Snapshot s) {
  if (s.frame < 0)
    throw std::invalid_argument("RenderThread::submit_frame: a movie frame needs its index");
  if (!queue_) return false;
  if (frames_in_flight_.fetch_add(1, std::memory_order_relaxed) == 0) report_busy();
  if (queue_->push_frame(std::move(s))) return true;
  frame_done();
  return false;
}

bool RenderThread::offer_preview(Snapshot s) {
  return queue_ && queue_->offer_preview(std::move(s));
}

RenderStats RenderThread::stop() {
  if (thread_.joinable()) {  // also while the set-up runs: it finishes (or fails), then the loop
                             // drains the queue
    queue_->close();
    thread_.join();
  }
  std::lock_guard<std::mutex> l(mu_);
  if (queue_) {
    stats_.producer_waits = queue_->producer_waits();
    stats_.previews_replaced = queue_->previews_replaced();
  }
  return stats_;
}

std::string RenderThread::error() const {
  std::lock_guard<std::mutex> l(mu_);
  return error_;
}

ContextInfo RenderThread::context_info() const {
  std::lock_guard<std::mutex> l(mu_);
  return info_;
}

}  // namespace capflow::render
