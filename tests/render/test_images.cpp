// Image tests with known answers, run for BOTH headless backends (EGL and OSMesa, forced);
// a backend this machine lacks is reported by GTEST_SKIP with the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "render/overlay.h"
#include "render/renderer.h"
#include "render_test_util.h"

namespace capflow::render {
namespace {
using testing::require_backend;
using testing::shape_snapshot;

bool is_background(const uint8_t* p) {
  return p[0] > 250 && p[1] > 250 && p[2] > 250;
}

// HSV hue in degrees of an RGB triple in [0,1]; chroma returned through *c.
double hue(double r, double g, double b, double* c) {
  const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
  *c = mx - mn;
  if (*c <= 0) return 0;
  double h;
  if (mx == r)
    h = std::fmod((g - b) / *c, 6.0);
  else if (mx == g)
    h = (b - r) / *c + 2;
  else
    h = (r - g) / *c + 4;
  h *= 60;
  return h < 0 ? h + 360 : h;
}

class Images : public ::testing::TestWithParam<Backend> {
 protected:
  RenderOptions base() const {
    RenderOptions o;
    o.backend = GetParam();
    o.width = 640;
    o.height = 480;
    o.overlay_colorbar = false;
    o.overlay_text = false;
    o.overlay_triad = false;  // the surface alone (AxisTriadFollowsTheCamera turns it on)
    o.element_lines = false;
    return o;
  }
};

TEST_P(Images, ContextReportsRequestedBackendAndRenderer) {
  require_backend(GetParam());
  Renderer r(base());
  EXPECT_EQ(r.context_info().backend, GetParam());
  EXPECT_FALSE(r.context_info().renderer.empty());
  EXPECT_NE(r.context_info().summary().find(backend_name(GetParam())), std::string::npos);
}

TEST_P(Images, OrthographicXYEllipsoidSilhouetteRatio) {
  require_backend(GetParam());
  RenderOptions o = base();
  o.camera.view = View::XY;
  o.camera.orthographic = true;
  o.field = ColorField::Plain;
  o.antialias = Antialias::Off;
  o.width = 1280;
  o.height = 960;
  Renderer r(o);
  Image img;
  r.render(shape_snapshot(10, 12, geometry::ellipsoid_map(1.8, 0.7, 1.0)), &img);
  // Without multisampling a pixel is covered iff its centre is inside the silhouette, so a
  // run of covered pixels measures an extent to +-1 px (0.25 % of the height here).
  const int cx = img.width / 2, cy = img.height / 2;
  double w = 0, h = 0;
  for (int x = 0; x < img.width; ++x) w += !is_background(img.pixel(x, cy));
  for (int y = 0; y < img.height; ++y) h += !is_background(img.pixel(cx, y));
  ASSERT_GT(h, 50);
  EXPECT_NEAR((w / h) / (1.8 / 0.7), 1.0, 0.01) << "width " << w << " px, height " << h << " px";
}

TEST_P(Images, ConstantFieldRendersUniformHueOfTheColormapLevel) {
  require_backend(GetParam());
  RenderOptions o = base();
  o.range_mode = capflow::render::RangeMode::Fixed;
  o.range_min = 0;
  o.range_max = 1;
  const double level = 0.7;
  Renderer r(o);
  Image img;
  r.render(shape_snapshot(6, 8, geometry::ellipsoid_map(1.3, 0.9, 1.0),
                          [](double, double, double) { return 0.7; }),
           &img);
  const auto want = r.colormap().at(level);
  double cw;
  const double want_h = hue(want[0], want[1], want[2], &cw);
  int counted = 0;
  double worst = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* p = img.pixel(x, y);
      if (is_background(p) || std::max({p[0], p[1], p[2]}) >= 254) continue;  // clamped
      double c;
      const double h = hue(p[0] / 255.0, p[1] / 255.0, p[2] / 255.0, &c);
      if (c < 0.25) continue;  // too dark / too pale for an 8-bit hue
      ++counted;
      double d = std::abs(h - want_h);
      worst = std::max(worst, std::min(d, 360 - d));
    }
  EXPECT_GT(counted, 10000);
  EXPECT_LT(worst, 3.0) << "degrees of hue; expected hue " << want_h;
}

// The lighting model of shaders/surface.vert (Blinn-Phong, two white lights fixed to the camera),
// evaluated exactly at a surface point: eye-space unit normal n, view direction v, base colour.
// The image of a sphere (every pixel that is not background): its centre and the radius of the
// disc of the same area, in pixels (to a fraction of a pixel).
struct Disc {
  double cx = 0, cy = 0, radius = 0, area = 0;
};
Disc disc_of(const Image& img) {
  Disc d;
  double sx = 0, sy = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (!is_background(img.pixel(x, y))) {
        sx += x + 0.5;
        sy += y + 0.5;
        d.area += 1;
      }
  if (d.area > 0) {
    d.cx = sx / d.area;
    d.cy = sy / d.area;
    d.radius = std::sqrt(d.area / M_PI);
  }
  return d;
}

std::array<double, 3> exact_lit(const std::array<float, 3>& base, const double n[3],
                                const double v[3]) {
  auto unit = [](double x, double y, double z) {
    const double r = std::sqrt(x * x + y * y + z * z);
    return std::array<double, 3>{x / r, y / r, z / r};
  };
  const auto key_dir = unit(0.0, 0.55, 1.0), fill_dir = unit(0.0, -0.7, 0.6);
  const auto half = unit(key_dir[0] + v[0], key_dir[1] + v[1], key_dir[2] + v[2]);
  auto dot = [n](const std::array<double, 3>& a) {
    return n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
  };
  const double d = 0.6 + 0.38 * std::max(dot(key_dir), 0.0) + 0.1 * std::max(dot(fill_dir), 0.0);
  const double sp = 0.04 * std::pow(std::max(dot(half), 0.0), 48.0);
  return {std::min(base[0] * d + sp, 1.0), std::min(base[1] * d + sp, 1.0),
          std::min(base[2] * d + sp, 1.0)};
}

// Every interior pixel of a unit sphere seen along z (orthographic, view XY: x right, y up, the
// eye on +z) carrying the field tau = x has the colour of the lighting model evaluated exactly at
// the surface point under the pixel centre, with the colour-map level of x there; pixels within
// 4 % of the radius of the silhouette are left out (the disc's centre and radius are measured
// from the image, to a fraction of a pixel).
TEST_P(Images, ShadingMatchesTheLightingModelAtTheExactSurfacePoint) {
  require_backend(GetParam());
  RenderOptions o = base();
  o.camera.view = View::XY;
  o.camera.orthographic = true;
  o.range_mode = capflow::render::RangeMode::Fixed;
  o.range_min = -1;
  o.range_max = 1;
  o.width = 1280;  // the sphere ~700 px across: each upsampled triangle spans ~10 px
  o.height = 960;
  Renderer r(o);
  Image img;
  r.render(shape_snapshot(6, 10, geometry::ellipsoid_map(1, 1, 1),
                          [](double x, double, double) { return x; }),
           &img);
  const Disc disc = disc_of(img);
  ASSERT_GT(disc.area, 20000);
  const double cx = disc.cx, cy = disc.cy, radius = disc.radius;
  const double v[3] = {0, 0, 1};
  int counted = 0, over2 = 0;
  double worst = 0, sum = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double px = (x + 0.5 - cx) / radius, py = (cy - y - 0.5) / radius;
      const double rr = px * px + py * py;
      if (rr > 0.96 * 0.96) continue;
      const double n[3] = {px, py, std::sqrt(1 - rr)};
      const auto want = exact_lit(r.colormap().at((px + 1) / 2), n, v);
      const uint8_t* p = img.pixel(x, y);
      double e = 0;
      for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(p[c] - 255.0 * want[c]));
      worst = std::max(worst, e);
      sum += e;
      over2 += e > 2.5;
      ++counted;
    }
  std::printf("shading: %d pixels, |colour - exact| mean %.2f, max %.2f levels, %d above 2.5\n",
              counted, sum / counted, worst, over2);
  EXPECT_LT(sum / counted, 1.0);
  EXPECT_LT(worst, 4.0);
  EXPECT_LT(over2, 0.01 * counted);
}

// CIELAB of an sRGB colour (components in [0, 1]), D65 white.
std::array<double, 3> lab(double r, double g, double b) {
  auto lin = [](double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  const double R = lin(r), G = lin(g), B = lin(b);
  const double X = (0.4124 * R + 0.3576 * G + 0.1805 * B) / 0.95047;
  const double Y = 0.2126 * R + 0.7152 * G + 0.0722 * B;
  const double Z = (0.0193 * R + 0.1192 * G + 0.9505 * B) / 1.08883;
  auto f = [](double t) {
    return t > 216.0 / 24389 ? std::cbrt(t) : (24389.0 / 27 * t + 16) / 116;
  };
  return {116 * f(Y) - 16, 500 * (f(X) - f(Y)), 200 * (f(Y) - f(Z))};
}

// The colour round trip, as a reader of the frame does it: every pixel of a unit sphere away
// from its silhouette (the surface turned at most 53 degrees from the viewer: r <= 0.8 of the
// disc) maps back, through the colour of the colour bar nearest to it in CIELAB, to the value
// drawn there (tau = x over the range [-1, 1]) within a few % of the range (below).
TEST_P(Images, ColoursMapBackToTheirValuesThroughTheColourBar) {
  require_backend(GetParam());
  for (ColorMap cm : {ColorMap::Viridis, ColorMap::CoolWarm}) {
    RenderOptions o = base();
    o.camera.view = View::XY;
    o.camera.orthographic = true;
    o.colormap = cm;
    o.element_lines = false;
    o.overlay_text = false;  // the image holds the sphere alone
    o.overlay_colorbar = false;
    o.range_mode = capflow::render::RangeMode::Fixed;
    o.range_min = -1;
    o.range_max = 1;
    o.width = 640;
    o.height = 480;
    Renderer r(o);
    Image img;
    r.render(shape_snapshot(6, 10, geometry::ellipsoid_map(1, 1, 1),
                            [](double x, double, double) { return x; }),
             &img);
    std::vector<std::array<double, 3>> bar(512);
    for (size_t k = 0; k < bar.size(); ++k) {
      const auto c = r.colormap().at(static_cast<double>(k) / (bar.size() - 1));
      bar[k] = lab(c[0], c[1], c[2]);
    }
    const Disc disc = disc_of(img);
    ASSERT_GT(disc.area, 5000);
    const double cx = disc.cx, cy = disc.cy, radius = disc.radius;
    double worst = 0, sum = 0;
    int counted = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const double px = (x + 0.5 - cx) / radius, py = (cy - y - 0.5) / radius;
        if (px * px + py * py > 0.8 * 0.8) continue;
        const uint8_t* p = img.pixel(x, y);
        const auto c = lab(p[0] / 255.0, p[1] / 255.0, p[2] / 255.0);
        size_t best = 0;
        double bd = 1e300;
        for (size_t k = 0; k < bar.size(); ++k) {
          const double d = std::pow(c[0] - bar[k][0], 2) + std::pow(c[1] - bar[k][1], 2) +
                           std::pow(c[2] - bar[k][2], 2);
          if (d < bd) {
            bd = d;
            best = k;
          }
        }
        const double value = -1 + 2.0 * best / (bar.size() - 1);
        const double e = std::abs(value - px) / 2;  // fraction of the range
        worst = std::max(worst, e);
        sum += e;
        ++counted;
      }
    std::printf("round trip (%s): %d pixels, |value - drawn| mean %.4f, max %.4f of the range\n",
                capflow::render::colormap_name(cm), counted, sum / counted, worst);
    // viridis changes luminance along the map, so the shading's darkening reads as a lower
    // value: 6 % of the range at most (12 % with the lighting before), 1.5 % on average;
    // coolwarm, whose luminance peaks in the middle, 3 %
    const bool viridis = cm == ColorMap::Viridis;
    EXPECT_LT(worst, viridis ? 0.065 : 0.03) << capflow::render::colormap_name(cm);
    EXPECT_LT(sum / counted, viridis ? 0.015 : 0.01) << capflow::render::colormap_name(cm);
  }
}

// The axis triad at the bottom left follows the camera: seen along -z (view xy) the red x axis
// points right and the green y axis up from their common origin; seen along -y (view xz) the blue
// z axis points up.
TEST_P(Images, AxisTriadFollowsTheCamera) {
  require_backend(GetParam());
  for (View view : {View::XY, View::XZ}) {
    RenderOptions o = base();
    o.camera.view = view;
    o.overlay_triad = true;
    Renderer r(o);
    Image img;
    r.render(shape_snapshot(6, 6, geometry::ellipsoid_map(1, 1, 1),
                            [](double, double, double) { return 0.0; }),
             &img);
    // centroids of the axis colours in the bottom-left corner, clear of the sphere (y down)
    double sum[3][3] = {};  // per colour: x, y, count
    for (int y = img.height * 3 / 4; y < img.height; ++y)
      for (int x = 0; x < img.width / 6; ++x) {
        const uint8_t* p = img.pixel(x, y);
        const int c = p[0] > 150 && p[1] < 90 && p[2] < 90     ? 0
                      : p[1] > 110 && p[0] < 90 && p[2] < 110  ? 1
                      : p[2] > 150 && p[0] < 100 && p[1] < 130 ? 2
                                                               : -1;
        if (c < 0) continue;
        sum[c][0] += x;
        sum[c][1] += y;
        sum[c][2] += 1;
      }
    const int up = view == View::XY ? 1 : 2;  // the axis drawn pointing up
    ASSERT_GT(sum[0][2], 20) << view_name(view);
    ASSERT_GT(sum[up][2], 20) << view_name(view);
    const double rx = sum[0][0] / sum[0][2], ry = sum[0][1] / sum[0][2];
    const double ux = sum[up][0] / sum[up][2], uy = sum[up][1] / sum[up][2];
    EXPECT_GT(rx - ux, 10) << view_name(view);  // x to the right of the upward axis
    EXPECT_GT(ry - uy, 10) << view_name(view);  // the upward axis above x
  }
}

TEST_P(Images, MirrorSymmetricShapeAndViewGiveMirrorSymmetricImage) {
  require_backend(GetParam());
  RenderOptions o = base();
  o.camera.view = View::XY;  // the lamellar shape is symmetric under x -> -x
  // Element edges stay off: 1-px lines rasterise with GL's half-open rules, not symmetrically.
  Renderer r(o);
  Image img;
  r.render(shape_snapshot(14, 10, geometry::lamellar_map(),
                          [](double x, double y, double) { return x * x + y; }),
           &img);
  double sum = 0;
  int big = 0, fg = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* p = img.pixel(x, y);
      const uint8_t* q = img.pixel(img.width - 1 - x, y);
      if (!is_background(p)) ++fg;
      // Silhouette pixels are excluded from the "big" count: the 4x MSAA sample pattern is
      // not mirror-symmetric, so partially covered pixels legitimately differ.
      bool edge = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, img.width - 1),
                    yy = std::clamp(y + dy, 0, img.height - 1);
          edge = edge || is_background(img.pixel(xx, yy)) ||
                 is_background(img.pixel(img.width - 1 - xx, yy));
        }
      for (int c = 0; c < 3; ++c) {
        const int d = std::abs(p[c] - q[c]);
        sum += d;
        if (d > 24 && !edge) ++big;
      }
    }
  ASSERT_GT(fg, 20000);
  std::printf("mirror: mean %.3f levels, %d of %d foreground pixels differ by > 24\n",
              sum / (3.0 * img.width * img.height), big, fg);
  EXPECT_LT(sum / (3.0 * img.width * img.height), 0.5);  // mean |difference| in 8-bit levels
  EXPECT_LT(big, 0.002 * fg);  // a few rasterisation differences along edges only
}

TEST_P(Images, ColorbarPixelsFollowTheColormap) {
  require_backend(GetParam());
  for (ColorMap cm : {ColorMap::Viridis, ColorMap::CoolWarm}) {
    RenderOptions o = base();
    o.overlay_colorbar = true;
    o.colormap = cm;
    Renderer r(o);
    Image img;
    r.render(shape_snapshot(6, 6, geometry::ellipsoid_map(1, 1, 1),
                            [](double x, double, double) { return x; }),
             &img);
    const ColorbarGeometry g = colorbar_geometry(img.width, img.height);
    const int x = static_cast<int>(0.5f * (g.x0 + g.x1));
    double worst = 0;
    int rows = 0;
    for (int y = static_cast<int>(g.y0) + 2; y <= static_cast<int>(g.y1) - 3; ++y) {
      const double t = (g.y1 - (y + 0.5)) / (g.y1 - g.y0);
      const auto want = r.colormap().at(t);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(img.pixel(x, y)[c] - 255.0 * want[c]));
      ++rows;
    }
    EXPECT_GT(rows, 200);
    EXPECT_LT(worst, 4.0) << colormap_name(cm) << ": max channel error in 8-bit levels";
  }
}

// Anti-aliasing by smooth lines (the default on llvmpipe) against 4x multisampling, on the
// lamellar shape with element lines and a colour field (1280x720, the movie size):
//  * silhouette: the covered pixels (not background) agree except in a band of one pixel;
//  * colours: away from the silhouette and the lines (2 px) the pixels agree to within 2 levels;
//  * edges: both give the silhouette intermediate (blended) pixels - as many within a factor of
//    two; without anti-aliasing there are none - and near the edges and lines the lines image
//    is closer to the multisampled one than the image without anti-aliasing.
TEST_P(Images, AntialiasLinesMatchesMultisampling) {
  require_backend(GetParam());
  const Snapshot s = shape_snapshot(6, 9, geometry::lamellar_map(),
                                    [](double x, double, double) { return x * x; });
  auto render_with = [&](Antialias aa, Antialias* used) {
    RenderOptions o = base();
    o.width = 1280;
    o.height = 720;
    o.element_lines = true;
    o.antialias = aa;
    o.msaa = 4;
    Renderer r(o);
    *used = r.antialias();
    Image img;
    r.render(s, &img);
    return img;
  };
  Antialias used_ms, used_lines, used_off;
  const Image ms = render_with(Antialias::Multisample, &used_ms);
  const Image ln = render_with(Antialias::Lines, &used_lines);
  const Image off = render_with(Antialias::Off, &used_off);
  ASSERT_EQ(used_lines, Antialias::Lines);
  ASSERT_EQ(used_off, Antialias::Off);
  long translucent = 0;  // the blended lines must leave the frame opaque (PNG alpha)
  for (size_t k = 3; k < ln.rgba.size(); k += 4) translucent += ln.rgba[k] != 255;
  EXPECT_EQ(translucent, 0);
  if (used_ms != Antialias::Multisample) GTEST_SKIP() << "no multisampling on this GL";
  const int w = ms.width, h = ms.height;
  auto fg = [](const Image& im, int x, int y) { return !is_background(im.pixel(x, y)); };
  // pixels within r of a jump of more than 12 levels (the shading changes by far less from one
  // pixel to the next): the silhouette and the element lines of either image
  auto near_edge = [&](const Image& im, int x, int y, int r) {
    const uint8_t* p = im.pixel(x, y);
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
        const uint8_t* q = im.pixel(xx, yy);
        for (int c = 0; c < 3; ++c)
          if (std::abs(p[c] - q[c]) > 12) return true;
      }
    return false;
  };
  long cover_diff = 0, cover_far = 0, silhouette = 0, interior = 0;
  double worst_interior = 0;
  long blended[3] = {0, 0, 0};  // MSAA, lines, off: silhouette pixels between background and fg
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const bool a = fg(ms, x, y), b = fg(ln, x, y);
      const bool edge = a != fg(ms, x + 1, y) || a != fg(ms, x, y + 1);
      silhouette += edge;
      if (a != b) {
        ++cover_diff;
        // more than one pixel away from the multisampled silhouette
        bool close = false;
        for (int dy = -1; dy <= 1 && !close; ++dy)
          for (int dx = -1; dx <= 1 && !close; ++dx) close = fg(ms, x + dx, y + dy) != a;
        cover_far += !close;
      }
      if (a && b && !near_edge(ms, x, y, 2) && !near_edge(ln, x, y, 2)) {
        ++interior;
        double d = 0;
        for (int c = 0; c < 3; ++c)
          d = std::max(d, std::abs(double(ms.pixel(x, y)[c]) - ln.pixel(x, y)[c]));
        worst_interior = std::max(worst_interior, d);
      }
      const Image* imgs[3] = {&ms, &ln, &off};
      for (int k = 0; k < 3; ++k) {
        const uint8_t* p = imgs[k]->pixel(x, y);
        const int mn = std::min({p[0], p[1], p[2]});
        // partially covered background: lighter than any surface colour, not white
        if (edge && mn > 120 && mn < 245) ++blended[k];
      }
    }
  // mean |difference| from the multisampled image over the pixels near its edges and lines
  auto edge_difference = [&](const Image& im) {
    double sum = 0;
    long n = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (near_edge(ms, x, y, 1)) {
          for (int c = 0; c < 3; ++c)
            sum += std::abs(double(ms.pixel(x, y)[c]) - im.pixel(x, y)[c]);
          n += 3;
        }
    return sum / std::max(1L, n);
  };
  const double diff_lines = edge_difference(ln), diff_off = edge_difference(off);
  std::printf(
      "antialias lines vs msaa: %ld silhouette px, coverage differs at %ld (%ld more than 1 px "
      "away); interior %ld px, max channel difference %.0f; blended silhouette px msaa %ld, lines "
      "%ld, off %ld; mean difference at edges and lines: lines %.1f, off %.1f levels\n",
      silhouette, cover_diff, cover_far, interior, worst_interior, blended[0], blended[1],
      blended[2], diff_lines, diff_off);
  ASSERT_GT(silhouette, 1000);
  EXPECT_EQ(cover_far, 0);
  EXPECT_LT(cover_diff, silhouette / 4);
  EXPECT_GT(interior, 50000);
  EXPECT_LE(worst_interior, 2.0);
  EXPECT_GT(blended[1], blended[0] / 2);
  EXPECT_LT(blended[1], 2 * blended[0]);
  EXPECT_LT(blended[2], blended[0] / 10);
  EXPECT_LT(diff_lines, 0.75 * diff_off);  // closer to multisampling than no anti-aliasing
}

// Culling the back faces (the default when the eye is outside the bounding box) changes a
// closed surface's image only where a back face seen edge-on covered a silhouette pixel: the
// element divisions and their orientations, named views in perspective and orthographic
// projection, a deformed shape.
TEST_P(Images, BackFaceCullingChangesOnlySilhouettePixels) {
  require_backend(GetParam());
  long compared = 0, worst = 0;
  for (int ne : {6, 10, 14})
    for (View view : {View::Oblique, View::XY, View::YZ})
      for (bool ortho : {false, true}) {
        const Snapshot s = shape_snapshot(ne, 7, geometry::lamellar_map(),
                                          [](double x, double y, double) { return x * y; });
        Image img[2];
        for (int cull = 0; cull < 2; ++cull) {
          RenderOptions o = base();
          o.width = 320;
          o.height = 240;
          o.element_lines = true;
          o.camera.view = view;
          o.camera.orthographic = ortho;
          o.cull_back_faces = cull == 1;
          Renderer r(o);
          r.render(s, &img[cull]);
        }
        ASSERT_EQ(img[0].rgba.size(), img[1].rgba.size());
        // a pixel may differ only on the silhouette (a back face seen edge-on beside the last
        // front face: background in the culled image within one pixel)
        long differ = 0, off_silhouette = 0;
        const int w = img[0].width, h = img[0].height;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            if (std::equal(img[0].pixel(x, y), img[0].pixel(x, y) + 3, img[1].pixel(x, y)))
              continue;
            ++differ;
            bool near_bg = false;
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx)
                near_bg = near_bg || is_background(img[1].pixel(std::clamp(x + dx, 0, w - 1),
                                                                std::clamp(y + dy, 0, h - 1)));
            off_silhouette += !near_bg;
          }
        const std::string what = "NE=" + std::to_string(ne) + " view " + view_name(view) +
                                 (ortho ? " orthographic" : " perspective");
        EXPECT_EQ(off_silhouette, 0) << what;
        EXPECT_LE(differ, 40) << what;  // of 76800 pixels
        worst = std::max(worst, differ);
        ++compared;
      }
  EXPECT_EQ(compared, 18);
  std::printf("back-face culling: at most %ld pixels differ, all on the silhouette\n", worst);
}

INSTANTIATE_TEST_SUITE_P(Backends, Images, ::testing::Values(Backend::Egl, Backend::OSMesa),
                         [](const auto& param_info) {
                           return std::string(backend_name(param_info.param));
                         });

}  // namespace
}  // namespace capflow::render
