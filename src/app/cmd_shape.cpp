// capflow shape: diagnostics of an analytic surface on the spectral mesh, as one JSON object.
//
//   capflow shape --elements 10 --nb 14 --ellipsoid 1.8,0.7,1.0
//   {"area":..., "volume":..., "L":..., "S":..., "W":..., "D":..., "Lc":..., "Sc":..., "Wc":...,
//    "edge_curvature":..., "max_mean_curvature_error":...}
//
// max_mean_curvature_error is the maximum over all nodes (edges and corners included) of
// |H_spectral - H_exact| for the sphere and ellipsoid; null for shapes without a closed form.
// edge_curvature is null where the +x axis through the centroid meets no surface.
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "control/record.h"
#include "diagnostics/diagnostics.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"

namespace capflow::app {
namespace {

struct ShapeArgs {
  int elements = 6;
  int nb = 12;
  std::string shape = "sphere";
  std::vector<double> ellipsoid;
  std::string map = "equiangular";
};

void run_shape(const ShapeArgs& a) {
  using namespace geometry;
  std::string shape = a.shape;
  double ea = 1, eb = 1, ec = 1;
  if (!a.ellipsoid.empty()) {
    if (a.ellipsoid.size() != 3)
      throw UserError("--ellipsoid takes three semi-axes A,B,C (got " +
                      std::to_string(a.ellipsoid.size()) + " values)");
    for (double v : a.ellipsoid)
      if (!(v > 0.0) || v > 100.0)
        throw UserError("--ellipsoid semi-axes must be in (0, 100], got " + std::to_string(v));
    ea = a.ellipsoid[0];
    eb = a.ellipsoid[1];
    ec = a.ellipsoid[2];
    if (shape == "sphere") shape = "ellipsoid";
    else if (shape != "ellipsoid")
      throw UserError("--ellipsoid goes with --shape ellipsoid, not --shape " + shape);
  } else if (shape == "ellipsoid") {
    throw UserError("--shape ellipsoid needs --ellipsoid A,B,C");
  }
  const Mesh mesh(a.elements, a.nb,
                  a.map == "radial" ? ElementMap::Radial : ElementMap::Equiangular);
  const PointMap f = (shape == "lamellar") ? lamellar_map() : ellipsoid_map(ea, eb, ec);
  const Matrix3Xd x = map_points(mesh.reference(), f);
  const diagnostics::ShapeDiagnostics d = diagnostics::measure_shape(mesh, x);

  control::Record out;
  out.set("area", d.area).set("volume", d.volume).set("L", d.L).set("S", d.S).set("W", d.W);
  out.set("D", d.D).set("Lc", d.Lc).set("Sc", d.Sc).set("Wc", d.Wc).set("edge_curvature", d.edge_curvature);
  if (shape == "lamellar") {
    out.set_json("max_mean_curvature_error", "null");
  } else {
    const SurfaceGeometry g = compute_geometry(mesh, x);
    double err = 0;
    for (int m = 0; m < mesh.num_local(); ++m)
      err = std::max(err, std::abs(g.mean_curvature[m] -
                                   ellipsoid_mean_curvature(ea, eb, ec, x.col(m))));
    out.set("max_mean_curvature_error", err);
  }
  std::cout << out.text(2) << std::endl;
}

void setup_shape(CLI::App& root) {
  auto args = std::make_shared<ShapeArgs>();
  CLI::App* c = root.add_subcommand(
      "shape", "Print the diagnostics of an analytic surface on the spectral mesh as JSON");
  c->add_option("--elements", args->elements, "Element division: 6, 10 or 14")
      ->check(CLI::IsMember({6, 10, 14}))
      ->capture_default_str();
  c->add_option("--nb", args->nb, "Gauss-Lobatto nodes per element direction")
      ->check(CLI::Range(3, 64))
      ->capture_default_str();
  c->add_option("--shape", args->shape, "sphere | ellipsoid | lamellar")
      ->check(CLI::IsMember({"sphere", "ellipsoid", "lamellar"}))
      ->capture_default_str();
  c->add_option("--ellipsoid", args->ellipsoid, "Ellipsoid semi-axes A,B,C along x,y,z")
      ->delimiter(',');
  c->add_option("--map", args->map, "Element parametrisation: equiangular | radial")
      ->check(CLI::IsMember({"equiangular", "radial"}))
      ->capture_default_str();
  c->callback([args] { run_shape(*args); });
}

}  // namespace

CAPFLOW_COMMAND(10, setup_shape);

}  // namespace capflow::app
