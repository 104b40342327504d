// capflow/app/render_args: the command line of `capflow render` - its options, and every check
// of their values before anything is read or drawn (so that a bad option exits 2 naming it, and
// the option fuzzer can run the same checks: tests/fuzz/fuzz_options.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/render_flags.h"
#include "render/options.h"

namespace capflow::app {

struct RenderArgs {
  std::string source;          // a run directory, .ckpt or .vtp (empty: an analytic shape)
  std::optional<double> time;  // with a run directory: the saved surface nearest to it
  bool camera_given = false;   // --view or --eye: instead of the run's camera
  bool shape_given = false;    // --shape, --ellipsoid or --demo
  int ne = 10, nb = 12;
  std::string shape = "ellipsoid", demo = "stretch", view = "oblique", out = "capflow.png";
  std::vector<double> ellipsoid{1.8, 0.7, 1.0}, eye, target, up;
  double fov = 30;
  bool ortho = false, no_lines = false, no_colorbar = false, no_text = false;
  int msaa = 4;
  std::string antialias = "auto";
  RenderFlags image;  // width 1280, height 720
};

// The semi-axes --ellipsoid takes (in units of the sphere's radius).
constexpr double kMinSemiAxis = 0.01, kMaxSemiAxis = 100;

// Adds the options to `sub`; call note_given() in its callback (which options were given).
void add_render_args(CLI::App* sub, RenderArgs* a);
void note_given(CLI::App* sub, RenderArgs* a);

// The renderer's options from the arguments, every value checked: UserError naming the option,
// the value and what is valid. The camera is the run's unless camera_given (the caller sets it).
render::RenderOptions check_render_args(const RenderArgs& a);

}  // namespace capflow::app
