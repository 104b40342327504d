#include "app/frames.h"

#include <cstdio>

#include "app/cpu_budget.h"
#include "app/errors.h"
#include "membrane/bending.h"
#include "membrane/membrane.h"

namespace capflow::app {

std::unique_ptr<render::RenderThread> start_renderer(const control::ControlOptions& opt,
                                                     RunDirectory& dir,
                                                     const std::string& movie_name, bool frames,
                                                     std::function<void(const std::string&)> say) {
  const bool want_frames = frames && (opt.output.png || opt.output.mp4.enabled);
  if (!want_frames && !opt.render.preview) return nullptr;
  render::RenderOptions ro = opt.render;
  ro.png = want_frames && opt.output.png;
  ro.png_dir = dir.file("frames").string();
  ro.mp4 = want_frames && opt.output.mp4.enabled;
  ro.mp4_path = dir.file(movie_name).string();
  ro.fps = opt.output.mp4.fps;
  ro.crf = opt.output.mp4.quality;
  ro.preview_path = dir.file("preview.png").string();
  if (ro.png) dir.subdirectory("frames");
  std::string err;
  if (!ro.IsValid(&err)) throw UserError("render options: " + err);
  const bool one_rasteriser = render_cpu_defaults();
  const bool renice = start_solver_threads();  // before the driver's dlopen (cpu_budget.h)
  auto renderer = std::make_unique<render::RenderThread>();
  // The renderer sets itself up (loading the GL driver is the larger part of a short run's
  // frame cost) while the solver builds and starts stepping; a set-up error reaches the run at
  // its next frame (submit_frame() returns false with the renderer's error()).
  renderer->launch(
      ro,
      [say](const std::string& line) {
        try {
          say(line);
        } catch (const std::exception&) {  // the renderer thread must not throw
        }
      },
      renderer_busy);
  if (one_rasteriser) say("render: LP_NUM_THREADS=1 (llvmpipe rasterises in one thread)");
  say(std::string("render: while a frame is pending the solver leaves the renderer a core") +
      (renice ? " and its idle threads wait at nice 19" : ""));
  return renderer;
}

std::string render_report(const render::RenderStats& rs) {
  std::string r = "renderer: " + std::to_string(rs.movie_frames) +
                  " movie frames written, solver waited " + std::to_string(rs.producer_waits) +
                  " times for the renderer";
  if (rs.movie_frames > 0) {
    const double n = static_cast<double>(rs.movie_frames);
    char b[200];
    std::snprintf(b, sizeof b,
                  "; ms per frame: upsample %.1f, draw %.1f, overlay %.1f, readback %.1f, "
                  "PNG %.1f, encode %.1f",
                  rs.total.upsample_ms / n, rs.total.draw_ms / n, rs.total.overlay_ms / n,
                  rs.total.readback_ms / n, rs.png_ms / n, rs.encode_ms / n);
    r += b;
  }
  return r;
}

render::Snapshot state_snapshot(const capsule::Capsule& cap, const Eigen::Matrix3Xd& x, double time,
                                double ca, const std::string& law,
                                const render::SnapshotDiagnostics& diag) {
  render::Snapshot sn;
  sn.ne = cap.mesh().ne();
  sn.nb = cap.mesh().nb();
  sn.x.assign(x.data(), x.data() + x.size());
  const membrane::MembraneFields f = cap.fields(x);
  sn.tau1.assign(f.tension1.data(), f.tension1.data() + f.tension1.size());
  sn.tau2.assign(f.tension2.data(), f.tension2.data() + f.tension2.size());
  if (cap.bending()) {
    const Eigen::VectorXd w = cap.bending()->energy_density(x);
    sn.bending.assign(w.data(), w.data() + w.size());
  }
  sn.time = time;
  sn.ca = ca;
  sn.law = law;
  sn.flow = cap.flow().description();  // the text block's flow line
  sn.diag = diag;
  return sn;
}

}  // namespace capflow::app
