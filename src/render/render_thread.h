// capflow/render/render_thread: the renderer thread driver.
//
//   RenderThread rt;
//   rt.start(options, log);            // spawns the thread; returns once its GL context,
//                                      // shaders and writers are ready (or throws their error)
//   (or rt.launch(options, log) ... rt.wait_ready(): the set-up runs while the caller goes on;
//    frames may be submitted before it is ready; if it fails the queue is closed, so
//    submit_frame() returns false and error() names the cause)
//   rt.submit_frame(snapshot);         // movie frame: BLOCKS while `queue_capacity` frames wait
//                                      // (back-pressure: frames are never dropped)
//   rt.offer_preview(snapshot);        // live preview: never blocks, only the latest is kept
//   RenderStats st = rt.stop();        // close the queue, render every queued frame, finish
//                                      // the MP4 (trailer), join. Idempotent; also run by ~.
//
// Per movie frame the thread renders (Renderer), writes <png_dir>/frame_NNNNNN.png when
// options.png (NNNNNN = the snapshot's frame index, so a resumed run continues the numbering) and
// appends to the MP4 when options.mp4. A preview is rendered and written atomically to
// options.preview_path. If rendering or writing fails the thread records the error, closes the
// queue (producers see false) and finishes the MP4; error() returns the message.
//
// Signals: install_stop_signal_handlers() makes SIGINT/SIGTERM set a flag that
// stop_requested() reports; the simulation loop polls it and calls stop(), so a signalled
// run still ends with a finalised movie. (SIGKILL cannot be caught: the fragmented MP4
// keeps the frames written before the last fragment flush.)
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "render/options.h"
#include "render/renderer.h"
#include "render/snapshot_queue.h"

namespace capflow::output {
class Mp4Writer;
}

namespace capflow::render {

struct RenderStats {
  long movie_frames = 0;             // rendered and written movie frames
  long previews = 0;                 // rendered previews
  long producer_waits = 0;           // times submit_frame() blocked (back-pressure)
  long previews_replaced = 0;        // previews superseded before being rendered
  FrameTimings total;                // summed stage times of movie frames (ms)
  double png_ms = 0, encode_ms = 0;  // summed write times (ms)
};

using LogFn = std::function<void(const std::string&)>;

class RenderThread {
 public:
  RenderThread() = default;
  ~RenderThread();
  RenderThread(const RenderThread&) = delete;
  RenderThread& operator=(const RenderThread&) = delete;

  // on_busy (optional) is called with true when a movie frame is submitted to an idle renderer
  // and with false when the last submitted frame has been written (from the submitting thread
  // and from the renderer thread respectively, one call at a time, the last call always the
  // present state; it must be cheap).
  // The set-up counts as a frame in flight: on_busy(true) when it begins, (false) when it and
  // every frame submitted meanwhile are done.
  void start(const RenderOptions& options, LogFn log = nullptr,
             std::function<void(bool)> on_busy = nullptr);
  void launch(const RenderOptions& options, LogFn log = nullptr,
              std::function<void(bool)> on_busy = nullptr);
  void wait_ready();  // rethrows the set-up's error
  bool submit_frame(Snapshot s);
  bool offer_preview(Snapshot s);
  RenderStats stop();
  // Blocks until every movie frame submitted so far is written (or the renderer failed).
  void wait_idle();
  // One past the index of the last movie frame whose files are written (its PNG, and its MP4
  // fragment), -1 before the first: what a checkpoint may count as on disk.
  long frames_written_through() const;

  bool running() const { return thread_.joinable(); }
  // True while the set-up runs and from submit_frame() until that frame's files are written
  // (movie frames only).
  bool busy() const { return frames_in_flight_.load(std::memory_order_relaxed) > 0; }
  std::string error() const;
  ContextInfo context_info() const;

 private:
  void run(std::promise<void> ready);  // the thread: set_up, then serve
  // The GL context (its summary logged), the PNG directory and the MP4 writer; throws.
  void set_up(std::unique_ptr<Renderer>* renderer, std::unique_ptr<output::Mp4Writer>* mp4);
  // Renders and writes every queued snapshot until the queue closes, then finishes the MP4.
  void serve(Renderer& renderer, output::Mp4Writer* mp4);
  void fail(const std::string& msg);
  void frame_done();  // one frame (or the set-up) fewer in flight
  // Calls on_busy_ if the state (frames in flight or not) changed since its last call: under
  // busy_mu_, so that a submit and a frame_done racing cannot leave the older state reported.
  void report_busy();
  RenderOptions opt_;
  LogFn log_;
  std::function<void(bool)> on_busy_;
  std::unique_ptr<SnapshotQueue> queue_;
  std::thread thread_;
  std::shared_future<void> ready_;
  mutable std::mutex mu_;  // guards error_, info_, stats_
  std::string error_;
  ContextInfo info_;
  RenderStats stats_;
  std::atomic<int> frames_in_flight_{0};
  std::atomic<long> written_through_{-1};
  std::mutex idle_mu_;
  std::condition_variable idle_cv_;
  std::mutex busy_mu_;  // serialises on_busy_ calls
  bool busy_reported_ = false;
};

void install_stop_signal_handlers();  // SIGINT, SIGTERM -> stop_requested() = true
bool stop_requested();

}  // namespace capflow::render
