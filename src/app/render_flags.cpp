#include "app/render_flags.h"

#include <sstream>

#include "app/commands.h"

namespace capflow::app {

void add_render_flags(CLI::App* sub, RenderFlags* f, const std::string& what) {
  sub->add_option("--width", f->width, what + "image width (px)");
  sub->add_option("--height", f->height, what + "image height (px)");
  sub->add_option("--field", f->field,
                  what + "colour: max | min | mean | bending (the bending energy density) | plain");
  sub->add_option("--colormap", f->colormap, "viridis | coolwarm (diverging, symmetric range)");
  sub->add_option("--range", f->range, "fixed colour range MIN,MAX (default: automatic)")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--backend", f->backend, "auto | egl | osmesa");
}

void apply_render_flags(const RenderFlags& f, render::RenderOptions* o) {
  using namespace capflow::render;
  if (f.width < 16 || f.width > kMaxWidth || f.width % 2)
    throw UserError("--width " + std::to_string(f.width) + ": an even number of pixels in [16, " +
                    std::to_string(kMaxWidth) + "]");
  if (f.height < 16 || f.height > kMaxHeight || f.height % 2)
    throw UserError("--height " + std::to_string(f.height) +
                    ": an even number of pixels in [16, " + std::to_string(kMaxHeight) + "]");
  o->width = f.width;
  o->height = f.height;
  if (!parse_field(f.field, &o->field))
    throw UserError("--field " + f.field + ": unknown (max | min | mean | bending | plain)");
  if (!parse_colormap(f.colormap, &o->colormap))
    throw UserError("--colormap " + f.colormap + ": unknown (viridis | coolwarm)");
  if (!parse_backend(f.backend, &o->backend))
    throw UserError("--backend " + f.backend + ": unknown (auto | egl | osmesa)");
  if (!f.range.empty()) {
    std::ostringstream given;
    for (size_t i = 0; i < f.range.size(); ++i) given << (i ? "," : "") << f.range[i];
    if (f.range.size() != 2) throw UserError("--range " + given.str() + ": needs MIN,MAX");
    const std::string why = render::fixed_range_problem(f.range[0], f.range[1]);
    if (!why.empty()) throw UserError("--range " + why);
    o->range_mode = render::RangeMode::Fixed;
    o->range_min = f.range[0];
    o->range_max = f.range[1];
  }
}

}  // namespace capflow::app
