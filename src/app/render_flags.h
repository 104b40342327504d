// capflow/app/render_flags: the image and colour flags that `capflow render` and
// `capflow figure` share (--width, --height, --field, --colormap, --range, --backend), and
// their validation into render::RenderOptions.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "render/renderer.h"

namespace capflow::app {

struct RenderFlags {
  int width = 1280, height = 720;
  std::string field = "max", colormap = "viridis", backend = "auto";
  std::vector<double> range;  // empty: automatic; else MIN,MAX
};

// Adds the flags to `sub`; `what` prefixes the help texts (e.g. "3-D view ").
void add_render_flags(CLI::App* sub, RenderFlags* flags, const std::string& what = "");

// Sets width, height, field, colour map, range and backend of `o` from the flags; throws
// UserError naming the flag for an unknown name or a range that is not MIN,MAX.
void apply_render_flags(const RenderFlags& flags, render::RenderOptions* o);

}  // namespace capflow::app
