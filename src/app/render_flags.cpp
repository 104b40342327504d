#include "app/render_flags.h"

#include "app/commands.h"

namespace capflow::app {

void add_render_flags(CLI::App* sub, RenderFlags* f, const std::string& what) {
  sub->add_option("--width", f->width, what + "image width (px)");
  sub->add_option("--height", f->height, what + "image height (px)");
  sub->add_option("--field", f->field, what + "colour: max | min | mean | plain");
  sub->add_option("--colormap", f->colormap, "viridis | coolwarm (diverging, symmetric range)");
  sub->add_option("--range", f->range, "fixed colour range MIN,MAX (default: automatic)")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--backend", f->backend, "auto | egl | osmesa");
}

void apply_render_flags(const RenderFlags& f, render::RenderOptions* o) {
  using namespace capflow::render;
  o->width = f.width;
  o->height = f.height;
  if (!parse_field(f.field, &o->field)) throw UserError("--field: unknown '" + f.field + "'");
  if (!parse_colormap(f.colormap, &o->colormap))
    throw UserError("--colormap: unknown '" + f.colormap + "'");
  if (!parse_backend(f.backend, &o->backend))
    throw UserError("--backend: unknown '" + f.backend + "'");
  if (!f.range.empty()) {
    if (f.range.size() != 2) throw UserError("--range needs MIN,MAX");
    o->range_mode = render::RangeMode::Fixed;
    o->range_min = f.range[0];
    o->range_max = f.range[1];
  }
}

}  // namespace capflow::app
