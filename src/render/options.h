// capflow/render/options: every setting of the renderer, as typed values. Filled by the CLI
// (`capflow render`) or by the JSON control file (src/control); nothing here parses files.
// The small parse_* helpers turn single option words into enums for those front ends.
#pragma once

#include <array>
#include <string>

#include "render/color_range.h"
#include "render/context.h"

namespace capflow::render {

// Named camera directions (eye direction as seen from the target, up vector):
//   Oblique: eye along (0.55, -0.75, 0.62) ~ the paper's 3-D views, up +z
//   XY: looking down -z, x right, y up;  XZ: looking along +y, x right, z up;
//   YZ: looking along -x, y right, z up;  Custom: eye/target/up below.
enum class View { Oblique, XY, XZ, YZ, Custom };

// Colour field: tau1 (max principal tension), tau2 (min), (tau1 + tau2)/2, plain colour; and
// for the live console (not a control-file choice) the mean curvature H (1/a: 1 on the unit
// sphere) and the nodes' speed |dx/dt| (G a), from the snapshot's optional arrays.
enum class ColorField {
  MaxTension,
  MinTension,
  MeanTension,
  Plain,
  MeanCurvature,
  Speed,
  BendingEnergy  // the bending energy density (kappa_b / 2)(2H - c0)^2
};
enum class ColorMap { Viridis, CoolWarm };  // assets/viridis.csv, assets/coolwarm.csv
// Edge anti-aliasing. Multisample: `msaa` samples per pixel. Lines: no multisampling; the element
// edges and the surface's outline (render/silhouette.h) are drawn as smooth (coverage-blended)
// lines, about a third of the CPU of 4x multisampling on llvmpipe (docs/performance.md). Auto:
// Lines on a software rasteriser (llvmpipe, softpipe, OSMesa's swrast), Multisample on a GPU.
enum class Antialias { Auto, Multisample, Lines, Off };

struct CameraOptions {
  View view = View::Oblique;
  bool orthographic = false;
  // Custom view (used when view == Custom): eye and target in world units, up direction.
  std::array<double, 3> eye{0, -6, 0}, target{0, 0, 0}, up{0, 0, 1};
  double fov_deg = 30;   // vertical field of view (perspective); ortho extent for Custom views
  double margin = 1.12;  // named views: frame the bounding box with this much room
};

// The largest image (8K UHD): the control file's render.width / height and the command line's.
constexpr int kMaxWidth = 7680, kMaxHeight = 4320;

// "" when a custom camera can be drawn from: eye, target and up finite (within +-1e6), the eye
// away from the target, up across the line of sight; else what is wrong, naming the value.
std::string custom_camera_problem(const CameraOptions& c);

struct RenderOptions {
  int width = 1280;  // image width in pixels (even; MP4 needs even sizes)
  int height = 720;  // image height in pixels (even)
  int msaa = 4;      // multisample count when multisampling (0 or 1 = off)
  Antialias antialias = Antialias::Auto;
  int subdivisions = 25;  // upsampling grid per element (25 x 25, as in the paper's views)
  CameraOptions camera;
  ColorField field = ColorField::MaxTension;
  ColorMap colormap = ColorMap::Viridis;
  // colour range (render/color_range.h): Grow (only grows over a movie), Frame (each frame's
  // own), Fixed ([range_min, range_max]); symmetric for CoolWarm
  RangeMode range_mode = RangeMode::Grow;
  double range_min = 0, range_max = 1;                    // used when range_mode is Fixed
  std::array<float, 3> plain_color{0.85f, 0.62f, 0.45f};  // sRGB, for ColorField::Plain
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};      // sRGB
  bool element_lines = true;                              // draw element edges as thin lines
  bool cull_back_faces = true;  // skip the back faces when the eye is outside the bounding box
                                // (the same image for a closed surface, a cheaper draw)
  std::array<float, 3> line_color{0.12f, 0.12f, 0.12f};
  bool overlay_colorbar = true;  // labelled colour bar (ignored for ColorField::Plain)
  bool overlay_text = true;      // t, Ca, D, law, flow
  bool overlay_triad = true;     // the world axes x, y, z at the bottom left
  Backend backend = Backend::Auto;

  // Outputs of the renderer thread (RenderThread); `capflow render` writes one PNG itself.
  bool png = true;  // write every movie frame as <png_dir>/frame_NNNNNN.png
  std::string png_dir = "frames";
  bool mp4 = false;  // write <mp4_path>, H.264 yuv420p fragmented MP4
  std::string mp4_path = "movie.mp4";
  int fps = 30;                      // movie frames per second
  int crf = 20;                      // x264 constant rate factor: 0 lossless .. 51 worst (quality)
  std::string preset = "ultrafast";  // x264 preset (speed/size trade-off; docs/performance.md)
  int flush_every = 1;               // write an MP4 fragment every N frames (kill -9 safety)
  bool preview = false;              // write the latest preview snapshot to preview_path
  std::string preview_path = "preview.png";
  int queue_capacity = 4;  // movie frames that may wait for the renderer

  // Checks ranges and combinations; on failure *error names the offending field.
  bool IsValid(std::string* error) const;
};

const char* view_name(View v);
const char* field_name(ColorField f);   // "max-tension", ...
const char* field_label(ColorField f);  // legend title (UTF-8), e.g. "τ₁ / Gₛ"
const char* colormap_name(ColorMap m);
const char* antialias_name(Antialias a);                     // "auto", "msaa", "lines", "off"
bool parse_view(const std::string& s, View* out);            // oblique|xy|xz|yz
bool parse_field(const std::string& s, ColorField* out);     // max|min|mean|plain (or long names)
bool parse_colormap(const std::string& s, ColorMap* out);    // viridis|coolwarm
bool parse_antialias(const std::string& s, Antialias* out);  // auto|msaa|lines|off

}  // namespace capflow::render
