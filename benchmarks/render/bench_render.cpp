// Renderer stage timings: ms per frame for upsample, draw (+MSAA resolve), readback, overlay,
// PNG (stb_image_write) and MP4 encode (libx264 veryfast + swscale) at 1280x720 and
// 1920x1080 for NE = 6, 10, 14 (NB = 12, 4x MSAA, element lines, colour bar + text).
// Prints a Markdown table of medians over `frames` frames (default 7). Backend: auto (EGL).
// Usage: bench_render [frames]
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "output/mp4_writer.h"
#include "output/png_writer.h"
#include "render/renderer.h"

using namespace capflow;

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(1, std::atoi(argv[1])) : 7;
  const std::string tmp = "/tmp/capflow_bench_render_" + std::to_string(::getpid());
  std::printf("| size | NE | upsample | draw | readback | overlay | PNG | encode | total |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  std::string backend;
  for (auto [w, h] : {std::pair{1280, 720}, std::pair{1920, 1080}}) {
    render::RenderOptions o;
    o.width = w;
    o.height = h;
    render::Renderer r(o);
    backend = r.context_info().summary();
    for (int ne : {6, 10, 14}) {
      geometry::Mesh mesh(ne, 12);
      const auto x = geometry::map_points(mesh.reference(), geometry::lamellar_map());
      render::Snapshot s;
      s.ne = ne;
      s.nb = 12;
      s.x.resize(3 * static_cast<size_t>(mesh.num_local()));
      s.tau1.resize(mesh.num_local());
      s.tau2.resize(mesh.num_local());
      for (int k = 0; k < mesh.num_local(); ++k) {
        for (int d = 0; d < 3; ++d) s.x[3 * k + d] = x(d, k);
        s.tau1[k] = s.tau2[k] = x(0, k) * x(0, k);
      }
      output::Mp4Options mo;
      mo.width = w;
      mo.height = h;
      output::Mp4Writer mp4(tmp + ".mp4", mo);
      std::vector<double> up, dr, rb, ov, png, enc;
      render::Image img;
      for (int f = 0; f < frames + 1; ++f) {
        render::FrameTimings t;
        r.render(s, &img, &t);
        auto t0 = std::chrono::steady_clock::now();
        output::write_png(tmp + ".png", w, h, img.rgba.data());
        const double p_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        t0 = std::chrono::steady_clock::now();
        mp4.add_frame(img.rgba.data());
        const double e_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (f == 0) continue;  // warm-up
        up.push_back(t.upsample_ms);
        dr.push_back(t.draw_ms);
        rb.push_back(t.readback_ms);
        ov.push_back(t.overlay_ms);
        png.push_back(p_ms);
        enc.push_back(e_ms);
      }
      mp4.finish();
      const double tot = median(up) + median(dr) + median(rb) + median(ov) + median(png) + median(enc);
      std::printf("| %dx%d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.0f |\n", w, h, ne,
                  median(up), median(dr), median(rb), median(ov), median(png), median(enc), tot);
      std::fflush(stdout);
    }
  }
  std::printf("\n%s\n", backend.c_str());
  std::remove((tmp + ".mp4").c_str());
  std::remove((tmp + ".png").c_str());
  return 0;
}
