#include "serve/frame_service.h"

#include <chrono>
#include <exception>

#include "output/jpeg_writer.h"
#include "output/png_writer.h"
#include "render/renderer.h"
#include "serve/orbit.h"

namespace capflow::serve {

struct FrameService::Job {
  std::shared_ptr<const render::Snapshot> snapshot;
  FrameQuery query;
  bool done = false;
  std::optional<EncodedFrame> frame;
  std::string error;
};

FrameService::FrameService(render::RenderOptions base, std::function<void(bool)> on_busy)
    : base_(std::move(base)), on_busy_(std::move(on_busy)) {
  // The console draws images; the movie's writers and preview stay the run's.
  base_.png = base_.mp4 = base_.preview = false;
  thread_ = std::thread([this] { loop(); });
}

FrameService::~FrameService() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::optional<EncodedFrame> FrameService::draw(std::shared_ptr<const render::Snapshot> s,
                                               const FrameQuery& q, std::string* error) {
  auto job = std::make_shared<Job>();
  job->snapshot = std::move(s);
  job->query = q;
  std::unique_lock<std::mutex> lock(mutex_);
  if (quit_ || static_cast<int>(jobs_.size()) >= kMaxWaiting) {
    *error = "the renderer is busy: " + std::to_string(kMaxWaiting) + " images wait already";
    return std::nullopt;
  }
  jobs_.push_back(job);
  wake_.notify_all();
  wake_.wait(lock, [&] { return job->done; });
  *error = job->error;
  return std::move(job->frame);
}

void FrameService::loop() {
  // The GL driver is loaded now, at the start, before a solver beside it starts its threads
  // (app/cpu_budget.h: start_solver_threads), not at the first request.
  try {
    FrameQuery first;
    first.width = base_.width;
    first.height = base_.height;
    first.field = base_.field;
    make_renderer(first);
  } catch (const std::exception&) {
    renderer_.reset();  // the first request tries again and reports the error
  }
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || !jobs_.empty(); });
      if (jobs_.empty()) break;  // quit_ with nothing left
      job = jobs_.front();
    }
    if (on_busy_) on_busy_(true);
    try {
      job->frame = render(*job->snapshot, job->query);
    } catch (const std::exception& e) {
      job->error = e.what();
    }
    if (on_busy_) on_busy_(false);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      jobs_.pop_front();
      job->done = true;
    }
    wake_.notify_all();
  }
  renderer_.reset();  // its GL context belongs to this thread
}

void FrameService::make_renderer(const FrameQuery& q) {
  if (renderer_ && key_w_ == q.width && key_h_ == q.height && key_field_ == q.field &&
      key_range_ == q.range)
    return;
  render::RenderOptions o = base_;
  o.width = q.width;
  o.height = q.height;
  o.field = q.field;
  o.range_mode = q.range;
  renderer_.reset();
  renderer_ = std::make_unique<render::Renderer>(o);
  key_w_ = q.width;
  key_h_ = q.height;
  key_field_ = q.field;
  key_range_ = q.range;
}

EncodedFrame FrameService::render(const render::Snapshot& s, const FrameQuery& q) {
  using clock = std::chrono::steady_clock;
  make_renderer(q);
  renderer_->set_camera(orbit_camera(q.orbit, s, base_.camera));
  EncodedFrame f;
  render::Image img;
  const auto t0 = clock::now();
  renderer_->render(s, &img);
  const auto t1 = clock::now();
  if (q.png) {
    f.bytes = output::encode_png(img.width, img.height, img.rgba.data());
    f.content_type = "image/png";
  } else {
    f.bytes = output::encode_jpeg(img.width, img.height, img.rgba.data());
    f.content_type = "image/jpeg";
  }
  f.draw_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  f.encode_ms = std::chrono::duration<double, std::milli>(clock::now() - t1).count();
  return f;
}

}  // namespace capflow::serve
