// Renderer stage costs per frame: wall and CPU milliseconds for upsample, draw (+ MSAA
// resolve), overlay, readback, PNG (libspng) and MP4 encode (libyuv + libx264), on a
// lamellar shape. CPU is the process's CPU time over the stage (every thread: the render thread,
// llvmpipe's rasteriser threads, x264's threads); nothing else runs in this process, so it is
// the stage's own cost. Prints a Markdown table of medians over `frames` frames after one
// warm-up frame.
// Usage: bench_render [--frames N] [--size WxH]... [--ne N]... [--nb N] [--msaa N]
//                     [--antialias auto|msaa|lines|off] [--preset P] [--no-png]
// Defaults: 7 frames, 1280x720 and 1920x1080, NE = 6, 10, 14, NB = 12, the renderer's defaults.
// Environment: LP_NUM_THREADS (llvmpipe's rasteriser threads) is read by Mesa as usual.
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "output/mp4_writer.h"
#include "output/png_writer.h"
#include "render/renderer.h"

using namespace capflow;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

double wall_ms() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "bench_render: %s\nusage: bench_render [--frames N] [--size WxH]... [--ne N]... "
               "[--nb N] [--msaa N] [--antialias auto|msaa|lines|off] [--preset P] [--no-png]\n",
               why);
  std::exit(2);
}

int to_int(const char* s, const char* what, int lo, int hi) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (!end || *end || v < lo || v > hi)
    usage((std::string(what) + " must be an integer in [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]")
              .c_str());
  return static_cast<int>(v);
}

struct Stage {
  std::vector<double> wall, cpu;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 7, nb = 12, msaa = -1;
  render::Antialias antialias = render::Antialias::Auto;
  bool png = true;
  std::string preset;
  std::vector<std::pair<int, int>> sizes;
  std::vector<int> nes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) usage((a + " needs a value").c_str());
      return argv[++i];
    };
    if (a == "--frames") {
      frames = to_int(next(), "--frames", 1, 10000);
    } else if (a == "--size") {
      const char* v = next();
      int w = 0, h = 0;
      if (std::sscanf(v, "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w % 2 || h % 2)
        usage("--size must be WxH, even, at least 16x16");
      sizes.emplace_back(w, h);
    } else if (a == "--ne") {
      const int ne = to_int(next(), "--ne", 6, 14);
      if (ne != 6 && ne != 10 && ne != 14) usage("--ne must be 6, 10 or 14");
      nes.push_back(ne);
    } else if (a == "--nb") {
      nb = to_int(next(), "--nb", 4, 24);
    } else if (a == "--msaa") {
      msaa = to_int(next(), "--msaa", 0, 16);
    } else if (a == "--antialias") {
      if (!render::parse_antialias(next(), &antialias))
        usage("--antialias must be auto, msaa, lines or off");
    } else if (a == "--preset") {
      preset = next();
    } else if (a == "--no-png") {
      png = false;
    } else if (std::isdigit(static_cast<unsigned char>(a[0]))) {
      frames = to_int(a.c_str(), "frames", 1, 10000);  // the older positional form
    } else {
      usage(("unknown argument " + a).c_str());
    }
  }
  if (sizes.empty()) sizes = {{1280, 720}, {1920, 1080}};
  if (nes.empty()) nes = {6, 10, 14};
  const std::string tmp = "/tmp/capflow_bench_render_" + std::to_string(::getpid());
  const char* names[6] = {"upsample", "draw", "overlay", "readback", "PNG", "encode"};
  std::printf("ms per frame, wall / CPU\n\n| size | NE");
  for (const char* n : names) std::printf(" | %s", n);
  std::printf(" | total |\n|---|---|---|---|---|---|---|---|---|\n");
  std::string backend;
  render::Antialias used_aa = antialias;
  for (auto [w, h] : sizes) {
    render::RenderOptions o;
    o.width = w;
    o.height = h;
    if (msaa >= 0) o.msaa = msaa;
    o.antialias = antialias;
    render::Renderer r(o);
    backend = r.context_info().summary();
    used_aa = r.antialias();
    for (int ne : nes) {
      geometry::Mesh mesh(ne, nb);
      const auto x = geometry::map_points(mesh.reference(), geometry::lamellar_map());
      render::Snapshot s;
      s.ne = ne;
      s.nb = nb;
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
      if (!preset.empty()) mo.preset = preset;
      output::Mp4Writer mp4(tmp + ".mp4", mo);
      Stage st[6];
      render::Image img;
      for (int f = 0; f < frames + 1; ++f) {
        render::FrameTimings t;
        r.render(s, &img, &t);
        double c0 = cpu_ms(), w0 = wall_ms();
        if (png) output::write_png(tmp + ".png", w, h, img.rgba.data());
        const double png_cpu = cpu_ms() - c0, png_wall = wall_ms() - w0;
        c0 = cpu_ms();
        w0 = wall_ms();
        mp4.add_frame(img.rgba.data());
        const double enc_cpu = cpu_ms() - c0, enc_wall = wall_ms() - w0;
        if (f == 0) continue;  // warm-up
        const double wall[6] = {t.upsample_ms, t.draw_ms, t.overlay_ms,
                                t.readback_ms, png_wall,  enc_wall};
        const double cpu[6] = {t.upsample_cpu_ms, t.draw_cpu_ms, t.overlay_cpu_ms,
                               t.readback_cpu_ms, png_cpu,       enc_cpu};
        for (int k = 0; k < 6; ++k) {
          st[k].wall.push_back(wall[k]);
          st[k].cpu.push_back(cpu[k]);
        }
      }
      mp4.finish();
      double tw = 0, tc = 0;
      std::printf("| %dx%d | %d |", w, h, ne);
      for (const Stage& k : st) {
        tw += median(k.wall);
        tc += median(k.cpu);
        std::printf(" %.1f / %.1f |", median(k.wall), median(k.cpu));
      }
      std::printf(" %.1f / %.1f |\n", tw, tc);
      std::fflush(stdout);
    }
  }
  std::printf("\n%s; anti-aliasing %s\n", backend.c_str(), render::antialias_name(used_aa));
  std::remove((tmp + ".mp4").c_str());
  std::remove((tmp + ".png").c_str());
  return 0;
}
