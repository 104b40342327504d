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
#include "app/render_args.h"
#include "app/saved_state.h"
#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"
#include "output/png_writer.h"
#include "render/renderer.h"

namespace capflow::app {
namespace {

// An analytic shape on the spectral mesh, coloured by a demonstration field.
render::Snapshot analytic_shape(const RenderArgs& c) {
  geometry::Mesh mesh(c.ne, c.nb);
  geometry::PointMap map;
  if (c.shape == "sphere")
    map = geometry::ellipsoid_map(1, 1, 1);
  else if (c.shape == "ellipsoid")
    map = geometry::ellipsoid_map(c.ellipsoid[0], c.ellipsoid[1], c.ellipsoid[2]);
  else
    map = geometry::lamellar_map();  // check_render_args took no other name
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

int run(const RenderArgs& c) {
  using namespace capflow::render;
  RenderOptions o = check_render_args(c);
  Snapshot s;
  if (!c.source.empty()) {
    SavedState st = load_saved_state(c.source, c.time);
    if (st.camera && !c.camera_given) o.camera = *st.camera;  // the run's camera
    console::err("render: " + st.note);
    s = std::move(st.snapshot);
  } else {
    s = analytic_shape(c);
  }
  try {
    Renderer r(o);
    console::err(r.context_info().summary());
    Image img;
    FrameTimings t;
    r.render(s, &img, &t);
    try {
      output::write_png(c.out, img.width, img.height, img.rgba.data());
    } catch (const std::runtime_error& e) {
      throw OutputError(e.what());
    }
    std::ostringstream m;
    m << "render: wrote " << c.out << " (" << img.width << "x" << img.height << ", upsample "
      << t.upsample_ms << " ms, draw " << t.draw_ms << " ms, overlay " << t.overlay_ms
      << " ms, readback " << t.readback_ms << " ms)";
    console::err(m.str());
  } catch (const OutputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw UserError(e.what());
  } catch (const std::runtime_error& e) {
    throw UserError(e.what());
  }
  return 0;
}

void setup(CLI::App& root) {
  auto c = std::make_shared<RenderArgs>();
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
  add_render_args(sub, c.get());
  sub->callback([c, sub] {
    note_given(sub, c.get());
    set_exit_code(run(*c));
  });
}

}  // namespace

CAPFLOW_COMMAND(20, setup);

}  // namespace capflow::app
