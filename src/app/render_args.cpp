// capflow/app/render_args: see render_args.h.
#include "app/render_args.h"

#include <array>
#include <cmath>
#include <sstream>

#include "app/errors.h"

namespace capflow::app {

namespace {

std::string numbers(const std::vector<double>& v) {
  std::ostringstream s;
  for (size_t i = 0; i < v.size(); ++i) s << (i ? "," : "") << v[i];
  return s.str();
}

std::array<double, 3> vec3(const std::vector<double>& v, const char* name) {
  if (v.size() != 3)
    throw UserError(std::string("--") + name + " " + numbers(v) + ": needs three numbers X,Y,Z");
  return {v[0], v[1], v[2]};
}

}  // namespace

void add_render_args(CLI::App* sub, RenderArgs* c) {
  sub->add_option("source", c->source,
                  "a run directory, a checkpoint (.ckpt) or a surface (.vtp) to draw (default: an "
                  "analytic shape)");
  sub->add_option("--time", c->time,
                  "with a run directory: the saved surface nearest to this time (default: the "
                  "newest checkpoint)");
  sub->add_option("--elements", c->ne, "NE: 6, 10 or 14")->check(CLI::IsMember({6, 10, 14}));
  sub->add_option("--nb", c->nb, "NB: Gauss-Lobatto nodes per element direction")
      ->check(CLI::Range(3, 64));
  sub->add_option("--shape", c->shape, "sphere | ellipsoid | lamellar");
  sub->add_option("--ellipsoid", c->ellipsoid, "semi-axes A,B,C of the ellipsoid")->delimiter(',');
  sub->add_option("--demo", c->demo, "demonstration field: stretch | x");
  sub->add_option("--view", c->view, "oblique | xy | xz | yz");
  sub->add_option("--eye", c->eye, "explicit eye X,Y,Z (overrides --view)")->delimiter(',');
  sub->add_option("--target", c->target, "explicit target X,Y,Z")->delimiter(',');
  sub->add_option("--up", c->up, "explicit up X,Y,Z")->delimiter(',');
  sub->add_option("--fov", c->fov, "vertical field of view in degrees");
  sub->add_flag("--ortho", c->ortho, "orthographic projection (default perspective)");
  sub->add_flag("--no-lines", c->no_lines, "do not draw element edges");
  sub->add_flag("--no-colorbar", c->no_colorbar, "no colour bar");
  sub->add_flag("--no-text", c->no_text, "no text block (t, Ca, D, law)");
  add_render_flags(sub, &c->image);
  sub->add_option(
      "--antialias", c->antialias,
      "auto | msaa | lines | off (auto: lines on a software rasteriser, msaa on a GPU)");
  sub->add_option("--msaa", c->msaa, "multisample count with --antialias msaa (0 = off)");
  sub->add_option("-o,--output", c->out, "output PNG");
}

void note_given(CLI::App* sub, RenderArgs* c) {
  c->camera_given = sub->get_option("--view")->count() + sub->get_option("--eye")->count() > 0;
  c->shape_given = sub->get_option("--shape")->count() + sub->get_option("--ellipsoid")->count() +
                       sub->get_option("--demo")->count() >
                   0;
}

render::RenderOptions check_render_args(const RenderArgs& c) {
  using namespace capflow::render;
  RenderOptions o;
  apply_render_flags(c.image, &o);
  if (c.msaa < 0 || c.msaa > 16)
    throw UserError("--msaa " + std::to_string(c.msaa) + ": a sample count in [0, 16]");
  o.msaa = c.msaa;
  if (!parse_antialias(c.antialias, &o.antialias))
    throw UserError("--antialias " + c.antialias + ": unknown (auto | msaa | lines | off)");
  if (!c.eye.empty()) {
    o.camera.view = View::Custom;
    o.camera.eye = vec3(c.eye, "eye");
    if (!c.target.empty()) o.camera.target = vec3(c.target, "target");
    if (!c.up.empty()) o.camera.up = vec3(c.up, "up");
  } else if (!parse_view(c.view, &o.camera.view)) {
    throw UserError("--view " + c.view + ": unknown (oblique | xy | xz | yz)");
  } else if (!c.target.empty() || !c.up.empty()) {
    throw UserError("--target and --up: only with --eye");
  }
  o.camera.orthographic = c.ortho;
  if (!(c.fov > 1 && c.fov < 170))
    throw UserError("--fov " + numbers({c.fov}) + ": the field of view must be in (1, 170) degrees");
  o.camera.fov_deg = c.fov;
  if (o.camera.view == View::Custom) {
    const std::string why = custom_camera_problem(o.camera);
    if (!why.empty()) throw UserError("--eye/--target/--up: " + why);
  }
  if (c.time && !std::isfinite(*c.time))
    throw UserError("--time " + numbers({*c.time}) + ": a finite time");
  if (c.source.empty()) {
    if (c.time) throw UserError("--time: only with a SOURCE (a run directory)");
    if (c.shape != "sphere" && c.shape != "ellipsoid" && c.shape != "lamellar")
      throw UserError("--shape " + c.shape + ": unknown (sphere | ellipsoid | lamellar)");
    if (c.demo != "stretch" && c.demo != "x")
      throw UserError("--demo " + c.demo + ": unknown (stretch | x)");
    if (c.shape == "ellipsoid") {
      if (c.ellipsoid.size() != 3)
        throw UserError("--ellipsoid " + numbers(c.ellipsoid) + ": needs three semi-axes A,B,C");
      for (double a : c.ellipsoid)
        if (!(a >= kMinSemiAxis && a <= kMaxSemiAxis))
          throw UserError("--ellipsoid " + numbers(c.ellipsoid) + ": every semi-axis must be in [" +
                          numbers({kMinSemiAxis}) + ", " + numbers({kMaxSemiAxis}) + "]");
    }
  } else if (c.shape_given) {
    throw UserError("--shape, --ellipsoid, --demo: only without a SOURCE");
  }
  o.element_lines = !c.no_lines;
  o.overlay_colorbar = !c.no_colorbar;
  o.overlay_text = !c.no_text;
  std::string err;
  if (!o.IsValid(&err)) throw UserError(err);
  return o;
}

}  // namespace capflow::app
