// capflow shape: diagnostics of an analytic surface on the spectral mesh, as one JSON object.
//
//   capflow shape --elements 10 --nb 14 --ellipsoid 1.8,0.7,1.0
//   capflow shape --shape biconcave --axis z       (the reference shapes of capsule.shape)
//   capflow shape --shape spheroid --aspect 0.5
//   {"area":..., "volume":..., "L":..., "S":..., "W":..., "D":..., "Lc":..., "Sc":..., "Wc":...,
//    "edge_curvature":..., "max_mean_curvature_error":...}
//
// max_mean_curvature_error is the maximum over all nodes (edges and corners included) of
// |H_spectral - H_exact| for the sphere and ellipsoid; null for shapes without a closed form.
// For the reference shapes (spheroid, biconcave; geometry/reference_shape.h) the exact values
// come from the 1-D profile (geometry/axisymmetric.h): "exact_area", "exact_volume" and the
// errors of the mesh's area, volume and nodal mean curvature against them, and the mesh's
// "element_quality" (smallest sqrt(g) ratio within an element, smallest tangent angle).
// Lengths in units of the equal-volume radius a. edge_curvature is null where the +x axis
// through the centroid meets no surface.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "control/record.h"
#include "diagnostics/diagnostics.h"
#include "geometry/reference_shape.h"
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
  double aspect = 0.5;
  std::string axis = "z";
};

// The reference shapes: diagnostics against the 1-D profile.
void reference_shape(const ShapeArgs& a, geometry::ReferenceShape::Kind kind) {
  using namespace geometry;
  if (!(a.aspect >= 0.1 && a.aspect <= 10))
    throw UserError("--aspect must be in [0.1, 10], got " + std::to_string(a.aspect));
  ReferenceShape rs;
  rs.kind = kind;
  rs.aspect = a.aspect;
  rs.axis = a.axis == "x" ? 0 : a.axis == "y" ? 1 : 2;
  const Mesh mesh(a.elements, a.nb,
                  a.map == "radial" ? ElementMap::Radial : ElementMap::Equiangular);
  const Matrix3Xd x = reference_positions(mesh, rs);
  const diagnostics::ShapeDiagnostics d = diagnostics::measure_shape(mesh, x);
  const AxisymmetricProfile p = profile_of(rs);
  const double area = static_cast<double>(profile_area(p));
  const double volume = static_cast<double>(profile_volume(p));
  const SurfaceGeometry g = compute_geometry(mesh, x);
  double err = 0;
  for (int m = 0; m < mesh.num_local(); ++m) {
    const long double th = theta_of(rs, mesh.reference().col(m));
    err = std::max(err, static_cast<double>(std::fabs(g.mean_curvature[m] -
                                                      profile_point(p, th).H)));
  }
  const ElementQuality q = element_quality(mesh, x);
  control::Record out;
  out.set("shape", shape_name(kind)).set("area", d.area).set("volume", d.volume);
  out.set("L", d.L).set("S", d.S).set("W", d.W).set("D", d.D);
  out.set("exact_area", area).set("exact_volume", volume);
  out.set("area_error", d.area - area).set("volume_error", d.volume - volume);
  out.set("max_mean_curvature_error", err);
  if (kind == ReferenceShape::Kind::Biconcave)
    out.set("reduced_volume", volume / (4 * M_PI / 3 * std::pow(area / (4 * M_PI), 1.5)));
  out.set("element_quality", control::Record()
                                 .set("min_jacobian_ratio", q.min_jacobian_ratio)
                                 .set("min_angle_deg", q.min_angle_deg));
  std::cout << out.text(2) << std::endl;
}

void run_shape(const ShapeArgs& a) {
  using namespace geometry;
  std::string shape = a.shape;
  if (shape == "spheroid" || shape == "biconcave") {
    if (!a.ellipsoid.empty()) throw UserError("--ellipsoid goes with --shape ellipsoid");
    return reference_shape(a, shape == "spheroid" ? ReferenceShape::Kind::Spheroid
                                                  : ReferenceShape::Kind::Biconcave);
  }
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
  c->add_option("--shape", args->shape, "sphere | ellipsoid | lamellar | spheroid | biconcave")
      ->check(CLI::IsMember({"sphere", "ellipsoid", "lamellar", "spheroid", "biconcave"}))
      ->capture_default_str();
  c->add_option("--aspect", args->aspect,
                "Spheroid: polar / equatorial semi-axis in [0.1, 10] (> 1 prolate)")
      ->capture_default_str();
  c->add_option("--axis", args->axis, "Spheroid and biconcave: the symmetry axis x | y | z")
      ->check(CLI::IsMember({"x", "y", "z"}))
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
