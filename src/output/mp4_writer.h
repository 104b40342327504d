// capflow/output/mp4_writer: an H.264 (libx264) yuv420p movie in a FRAGMENTED MP4, written
// progressively with libavformat/libavcodec (FFmpeg 5.1). No GL, no numerics.
//
// Robustness: the file starts with an empty moov and gets a moof+mdat fragment every
// `flush_every` frames (movflags frag_custom+empty_moov+default_base_moof, and an avio flush),
// so a process killed with SIGKILL leaves a playable file holding every frame written before
// the last fragment flush. x264 runs with tune=zerolatency (no frame delay), so a fragment
// holds exactly the frames added before the flush. finish() (or the destructor) drains the
// encoder and writes the trailer (mfra index): call it on normal exit and from the signal
// path (see render/render_thread.h).
// Timing: frame k has pts k in time base 1/fps and duration 1 (x264 leaves 0, which makes
// ffprobe under-report the duration), so duration = frames / fps.
// Failures: a write that fails (disk full, read-only, a file-size limit; seen in the I/O
// context's error after every fragment, not only in the return codes) throws, and the file is cut
// back to its last whole fragment first, so it stays playable with every frame of the fragments
// before; a movie that holds no frame then (or at finish()) is removed. After a failure the
// writer is closed.
// Errors: std::runtime_error with the FFmpeg error text; odd sizes -> std::invalid_argument.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace capflow::output {

struct Mp4Options {
  int width = 0, height = 0;         // pixels, both even
  int fps = 30;                      // frames per second
  int crf = 20;                      // x264 constant rate factor 0..51 (lower = better)
  std::string preset = "ultrafast";  // x264 preset (docs/performance.md, "x264")
  int flush_every = 1;               // frames per fragment
  // libx264's threads (0: its default, ~1.5 per core). 1 keeps the encoder on the calling thread:
  // the renderer's one-core budget (app/cpu_budget.h).
  int threads = 1;
};

class Mp4Writer {
 public:
  Mp4Writer(const std::string& path, const Mp4Options& options);
  ~Mp4Writer();  // finish(), errors swallowed
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  // One frame, 8-bit RGBA, rows top-down `stride` bytes apart (0: width*4).
  void add_frame(const uint8_t* rgba, int stride = 0);
  void flush();   // writes the pending fragment to disk now
  void finish();  // drains the encoder, writes the trailer, closes the file; idempotent
  long frames() const { return frames_; }
  long frames_in_file() const;  // frames in the file's whole fragments

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  long frames_ = 0;
};

}  // namespace capflow::output
