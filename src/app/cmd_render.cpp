// capflow render: draws a surface to a PNG without running the solver (headless figures).
//
// A saved state (app/saved_state.h): a run directory (the surface nearest to --time, or the
// newest checkpoint), a checkpoint or a .vtp surface, with the run's camera unless --view or
// --eye says otherwise. Without a source: an analytic shape (sphere, ellipsoid, lamellar) on
// the NE-element spectral mesh, coloured by a demonstration field computed from the shape
// (--demo), since there are no tensions without the solver.
//
// Example:
//   capflow render runs/capflow --time 2.5 -o t2.5.png
//   capflow render --shape ellipsoid --ellipsoid 1.8,0.7,1.0 --elements 10 -o ellipsoid.png
//   capflow render --shape lamellar --demo x --colormap coolwarm --view xy -o lamellar.png
#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "app/commands.h"
#include "app/console.h"
#include "app/render_flags.h"
#include "app/saved_state.h"
#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"
#include "output/png_writer.h"
#include "render/renderer.h"

namespace capflow::app {
namespace {

struct RenderCmd {
  std::string source;          // a run directory, .ckpt or .vtp (empty: an analytic shape)
  std::optional<double> time;  // with a run directory: the saved surface nearest to it
  bool camera_given = false;   // --view or --eye: instead of the run's camera
  bool shape_given = false;
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

// An analytic shape on the spectral mesh, coloured by a demonstration field.
render::Snapshot analytic_shape(const RenderCmd& c) {
  geometry::Mesh mesh(c.ne, c.nb);
  geometry::PointMap map;
  if (c.shape == "sphere")
    map = geometry::ellipsoid_map(1, 1, 1);
  else if (c.shape == "ellipsoid") {
    if (c.ellipsoid.size() != 3)
      throw UserError("--ellipsoid needs three semi-axes A,B,C, got " +
                      std::to_string(c.ellipsoid.size()) + " numbers");
    for (double a : c.ellipsoid)
      if (!(a >= kMinSemiAxis && a <= kMaxSemiAxis))
        throw UserError("--ellipsoid " + numbers(c.ellipsoid) + ": every semi-axis must be in [" +
                        numbers({kMinSemiAxis}) + ", " + numbers({kMaxSemiAxis}) + "]");
    map = geometry::ellipsoid_map(c.ellipsoid[0], c.ellipsoid[1], c.ellipsoid[2]);
  } else if (c.shape == "lamellar")
    map = geometry::lamellar_map();
  else
    throw UserError("--shape: unknown '" + c.shape + "' (sphere|ellipsoid|lamellar)");
  const auto x = geometry::map_points(mesh.reference(), map);

  render::Snapshot s;
  s.ne = c.ne;
  s.nb = c.nb;
  const int n = mesh.num_local();
  s.x.resize(3 * static_cast<size_t>(n));
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d) s.x[3 * k + d] = x(d, k);
  s.tau1.resize(n);
  s.tau2.resize(n);
  if (c.demo == "stretch") {
    // Principal stretches of the map sphere -> shape: eigenvalues lambda^2 of G0^-1 G.
    const auto g0 = geometry::compute_geometry(mesh, mesh.reference());
    const auto g = geometry::compute_geometry(mesh, x);
    for (int k = 0; k < n; ++k) {
      const double d0 = g0.g11[k] * g0.g22[k] - g0.g12[k] * g0.g12[k];
      const double m11 = (g0.g22[k] * g.g11[k] - g0.g12[k] * g.g12[k]) / d0;
      const double m22 = (g0.g11[k] * g.g22[k] - g0.g12[k] * g.g12[k]) / d0;
      const double tr = m11 + m22;
      const double det = (g.g11[k] * g.g22[k] - g.g12[k] * g.g12[k]) / d0;
      const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
      s.tau1[k] = std::sqrt(0.5 * tr + disc);
      s.tau2[k] = std::sqrt(std::max(0.0, 0.5 * tr - disc));
    }
  } else if (c.demo == "x") {
    for (int k = 0; k < n; ++k) s.tau1[k] = s.tau2[k] = x(0, k);
  } else {
    throw UserError("--demo: unknown '" + c.demo + "' (stretch|x)");
  }
  // Deformation parameter from the extents in the shear (xy) plane.
  double lx = 0, ly = 0;
  for (int k = 0; k < n; ++k) {
    lx = std::max(lx, std::abs(x(0, k)));
    ly = std::max(ly, std::abs(x(1, k)));
  }
  s.diag.D = (lx - ly) / (lx + ly);
  s.law = "analytic shape (" + c.shape + ", demo field: " + c.demo + ")";
  return s;
}

int run(const RenderCmd& c) {
  using namespace capflow::render;
  RenderOptions o;
  apply_render_flags(c.image, &o);
  o.msaa = c.msaa;
  if (!parse_antialias(c.antialias, &o.antialias))
    throw UserError("--antialias: unknown '" + c.antialias + "' (auto | msaa | lines | off)");
  if (!c.eye.empty()) {
    o.camera.view = View::Custom;
    o.camera.eye = vec3(c.eye, "eye");
    if (!c.target.empty()) o.camera.target = vec3(c.target, "target");
    if (!c.up.empty()) o.camera.up = vec3(c.up, "up");
  } else if (!parse_view(c.view, &o.camera.view)) {
    throw UserError("--view: unknown '" + c.view + "'");
  }
  o.camera.orthographic = c.ortho;
  o.camera.fov_deg = c.fov;
  if (!(c.fov > 1 && c.fov < 170))
    throw UserError("--fov " + numbers({c.fov}) + ": the field of view must be in (1, 170) degrees");
  if (o.camera.view == View::Custom) {
    const std::string why = custom_camera_problem(o.camera);
    if (!why.empty()) throw UserError("--eye/--target/--up: " + why);
  }
  Snapshot s;
  if (!c.source.empty()) {
    if (c.shape_given) throw UserError("--shape, --ellipsoid, --demo: only without a SOURCE");
    SavedState st = load_saved_state(c.source, c.time);
    if (st.camera && !c.camera_given) o.camera = *st.camera;
    console::err("render: " + st.note);
    s = std::move(st.snapshot);
  } else {
    if (c.time) throw UserError("--time: only with a SOURCE (a run directory)");
    s = analytic_shape(c);
  }
  o.element_lines = !c.no_lines;
  o.overlay_colorbar = !c.no_colorbar;
  o.overlay_text = !c.no_text;
  std::string err;
  if (!o.IsValid(&err)) throw UserError(err);

  try {
    Renderer r(o);
    console::err(r.context_info().summary());
    Image img;
    FrameTimings t;
    r.render(s, &img, &t);
    output::write_png(c.out, img.width, img.height, img.rgba.data());
    std::ostringstream m;
    m << "render: wrote " << c.out << " (" << img.width << "x" << img.height << ", upsample "
      << t.upsample_ms << " ms, draw " << t.draw_ms << " ms, overlay " << t.overlay_ms
      << " ms, readback " << t.readback_ms << " ms)";
    console::err(m.str());
  } catch (const std::invalid_argument& e) {
    throw UserError(e.what());
  } catch (const std::runtime_error& e) {
    throw UserError(e.what());
  }
  return 0;
}

void setup(CLI::App& root) {
  auto c = std::make_shared<RenderCmd>();
  CLI::App* sub = root.add_subcommand(
      "render",
      "Render a surface to a PNG without running the solver (headless figure).\n"
      "SOURCE: a run directory (its newest checkpoint, or with --time the saved surface\n"
      "nearest to it), a checkpoint (.ckpt) or a surface (.vtp), drawn with the run's camera.\n"
      "Without a SOURCE, an analytic shape; there are no tensions without the solver, so\n"
      "the colour field shows a demonstration\n"
      "field computed from the shape (--demo): 'stretch' puts the principal stretches\n"
      "lambda1 >= lambda2 of the map unit sphere -> shape where tau1, tau2 would be (so\n"
      "--field max shows lambda1, min lambda2, mean their average; all 1 on the sphere);\n"
      "'x' puts the x coordinate in both (a signed field, try --colormap coolwarm).");
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
  sub->callback([c, sub] {
    c->camera_given = sub->get_option("--view")->count() + sub->get_option("--eye")->count() > 0;
    c->shape_given = sub->get_option("--shape")->count() + sub->get_option("--ellipsoid")->count() +
                         sub->get_option("--demo")->count() >
                     0;
    set_exit_code(run(*c));
  });
}

}  // namespace

CAPFLOW_COMMAND(20, setup);

}  // namespace capflow::app
