#include "app/frames.h"

#include "app/cpu_budget.h"
#include "app/errors.h"
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
  auto renderer = std::make_unique<render::RenderThread>();
  try {
    renderer->start(
        ro,
        [say](const std::string& line) {
          try {
            say(line);
          } catch (const std::exception&) {  // the renderer thread must not throw
          }
        },
        renderer_busy);
  } catch (const std::exception& e) {
    throw OutputError(std::string("cannot render frames: ") + e.what());
  }
  if (one_rasteriser && renderer->context_info().renderer.find("llvmpipe") != std::string::npos)
    say("render: llvmpipe with one rasteriser thread (LP_NUM_THREADS=1); the solver leaves it a "
        "core while a frame is pending");
  return renderer;
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
  sn.time = time;
  sn.ca = ca;
  sn.law = law;
  sn.diag = diag;
  return sn;
}

}  // namespace capflow::app
