// capflow/render/renderer: one Snapshot -> one RGBA image, off-screen.
//
// Pipeline per frame (each stage timed in FrameTimings, milliseconds, GL stages end with
// glFinish so the figures are wall-clock costs):
//   upsample  : Upsampler (CPU) -> triangles, smooth normals, field values
//   draw      : upload, Blinn-Phong surface (+ element edges) into a multisampled FBO,
//               resolve (blit) into a single-sample FBO; or, with Antialias::Lines, straight
//               into the single-sample FBO with the element edges and the outline as smooth,
//               blended lines
//   overlay   : Dear ImGui colour bar and text into the resolved FBO
//   readback  : glReadPixels and vertical flip into Image (rows top-down)
// Colour range: render/color_range.h over the upsampled field's [min, max] of every frame this
// renderer draws (options.range_mode: Grow by default, so a movie keeps one range that only
// grows; symmetric for diverging maps). Values outside a fixed range clamp, and the colour bar
// marks them.
//
// Ownership/threads: the constructor creates the GL context (GlContext::create) in the calling
// thread; every later call must come from that same thread. Throws std::runtime_error on
// context, shader, asset or framebuffer failure (messages name the file / GL status).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/colormap.h"
#include "render/context.h"
#include "render/options.h"
#include "render/silhouette.h"
#include "render/snapshot.h"
#include "render/upsample.h"

namespace capflow::render {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width*height*4, row 0 = top
  const uint8_t* pixel(int x, int y) const {
    return &rgba[(static_cast<size_t>(y) * width + x) * 4];
  }
};

struct FrameTimings {
  double upsample_ms = 0, draw_ms = 0, overlay_ms = 0, readback_ms = 0;
  // The process's CPU time over each stage (every thread, llvmpipe's included): the stage's own
  // CPU cost only when nothing else runs in the process (benchmarks/render/bench_render).
  double upsample_cpu_ms = 0, draw_cpu_ms = 0, overlay_cpu_ms = 0, readback_cpu_ms = 0;
};

class Overlay;

class Renderer {
 public:
  explicit Renderer(const RenderOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  void render(const Snapshot& s, Image* out, FrameTimings* timings = nullptr);

  const ContextInfo& context_info() const { return context_->info(); }
  const RenderOptions& options() const { return opt_; }
  // The camera of the next frames (the colour range and everything else stay).
  void set_camera(const CameraOptions& c) { opt_.camera = c; }
  // The multisample count in use (0: none): the largest the GL supports up to options().msaa.
  int msaa() const { return msaa_used_; }
  // The anti-aliasing in use (options().antialias with Auto resolved for this GL).
  Antialias antialias() const { return antialias_; }
  // What differs from the options asked for (e.g. a lower msaa), one line each.
  const std::vector<std::string>& warnings() const { return warnings_; }
  const Colormap& colormap() const { return colormap_; }
  // Range and camera of the last rendered frame.
  double last_vmin() const { return vmin_; }
  double last_vmax() const { return vmax_; }
  const Camera& last_camera() const { return camera_; }

 private:
  void create_framebuffers();
  void draw_outline();
  RenderOptions opt_;
  std::unique_ptr<GlContext> context_;
  Colormap colormap_;
  std::unique_ptr<Upsampler> upsampler_;
  int upsampler_nb_ = 0;
  SurfaceMesh mesh_;
  std::unique_ptr<Overlay> overlay_;
  Camera camera_;
  double vmin_ = 0, vmax_ = 1;
  std::unique_ptr<ColorRange> range_;
  unsigned surface_prog_ = 0, lines_prog_ = 0;
  unsigned vao_ = 0, vbo_[3] = {0, 0, 0}, ebo_tri_ = 0, ebo_lines_ = 0, cmap_tex_ = 0;
  size_t vbo_capacity_[3] = {0, 0, 0};  // bytes of storage in vbo_ (upload_vertices)
  unsigned msaa_fbo_ = 0, msaa_rb_[2] = {0, 0}, fbo_ = 0, rb_[2] = {0, 0};
  int msaa_used_ = 0;
  Antialias antialias_ = Antialias::Off;
  OutlineLines outline_;  // Antialias::Lines: the outline of the last frame
  unsigned outline_vao_ = 0, outline_vbo_[3] = {0, 0, 0};
  size_t outline_capacity_[3] = {0, 0, 0};
  std::vector<std::string> warnings_;
  size_t uploaded_indices_ = 0;
  std::vector<uint8_t> readback_;
};

}  // namespace capflow::render
