// capflow/serve/frame_service: the live console's images, drawn by capflow's own off-screen
// renderer (render/renderer.h: the movie frames' shading, colour bar and HUD) on a thread of its
// own, apart from the run's movie renderer, so that a client's drags never wait for a movie frame
// and the solver never waits for a client.
//
// draw() hands a state and a query to the thread and waits for the encoded image. One renderer
// is kept for the last (size, field, range) asked for; another combination makes a new one (its
// GL context: ~0.05 s). At most kMaxWaiting requests wait: more are refused at once (busy), so
// that a flood of requests queues nothing. The first renderer (the run's size and field) is made
// when the service starts, so that the GL driver is loaded before a solver starts its threads.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "render/options.h"
#include "render/snapshot.h"
#include "serve/frame_drawer.h"
#include "serve/frame_query.h"

namespace capflow::render {
class Renderer;
}

namespace capflow::serve {

class FrameService : public FrameDrawer {
 public:
  static constexpr int kMaxWaiting = 4;

  // `base`: the run's render settings (colour map, background, overlay, anti-aliasing).
  // `on_busy` (optional): called with true before an image is drawn and false after it, so that
  // a solver beside it can leave it a core (app/cpu_budget.h).
  explicit FrameService(render::RenderOptions base, std::function<void(bool)> on_busy = nullptr);
  ~FrameService();
  FrameService(const FrameService&) = delete;
  FrameService& operator=(const FrameService&) = delete;

  // The image of `s` as `q` asks; nullopt when kMaxWaiting requests already wait (*error says
  // so) or drawing failed (*error: the renderer's message).
  std::optional<EncodedFrame> draw(std::shared_ptr<const render::Snapshot> s, const FrameQuery& q,
                                   std::string* error) override;

 private:
  struct Job;
  void loop();
  EncodedFrame render(const render::Snapshot& s, const FrameQuery& q);
  void make_renderer(const FrameQuery& q);

  render::RenderOptions base_;
  std::function<void(bool)> on_busy_;
  std::unique_ptr<render::Renderer> renderer_;
  int key_w_ = 0, key_h_ = 0;
  render::ColorField key_field_{};
  render::RangeMode key_range_{};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<Job>> jobs_;
  bool quit_ = false;
  std::thread thread_;
};

}  // namespace capflow::serve
