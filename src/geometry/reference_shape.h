// capflow/geometry/reference_shape: the capsule's stress-free reference shape, which is also its
// initial shape, as a map of the reference (unit) sphere's nodes. Lengths stay in units of the
// equal-volume radius a: every shape encloses 4 pi / 3.
//
//   sphere     X -> X (the default: the reference nodes unchanged, bit for bit)
//   spheroid   aspect r = polar / equatorial semi-axis (prolate r > 1, oblate r < 1) along `axis`:
//              X -> (s X_perp, r s X_axis) with s = r^(-1/3)
//   biconcave  the Evans & Fung red blood cell (geometry/axisymmetric.h) about `axis`:
//              X -> (R X_perp, X_axis Q(|X_perp|^2)) / a_EF, a_EF = 2.8215 um its equal-volume
//              radius (reduced volume ~0.64)
// Both maps are polynomials in the sphere's coordinates (sin(theta) = |X_perp|, cos(theta) =
// |X_axis|), so a node's meridian angle on the profile is known exactly: the reference values
// of area, volume and curvature at each node come from the 1-D profile (profile_of, theta_of).
// The shapes keep the mirror planes x = 0, y = 0, z = 0 for any axis along x, y or z.
#pragma once

#include <string>

#include "geometry/axisymmetric.h"
#include "geometry/shapes.h"

namespace capflow::geometry {

struct ReferenceShape {
  enum class Kind { Sphere, Spheroid, Biconcave };
  Kind kind = Kind::Sphere;
  double aspect = 1;  // spheroid: polar / equatorial semi-axis, in [0.1, 10]
  int axis = 2;       // the symmetry axis: 0 x, 1 y, 2 z
  bool is_sphere() const { return kind == Kind::Sphere; }
};

const char* shape_name(ReferenceShape::Kind k);  // "sphere", "spheroid", "biconcave"

// The map of the unit sphere onto the shape (scaled to the unit equal-volume radius).
PointMap reference_shape_map(const ReferenceShape& s);
// The shape's nodes on `mesh` (mesh.reference() itself for the sphere).
Matrix3Xd reference_positions(const Mesh& mesh, const ReferenceShape& s);

// The shape's meridian profile, scaled to the unit equal-volume radius, and the meridian angle
// of the point the sphere point X maps to (theta in [0, pi/2], the same for z and -z).
AxisymmetricProfile profile_of(const ReferenceShape& s);
long double theta_of(const ReferenceShape& s, const Vector3d& X);

// Element quality of a surface on its mesh: over every element, the smallest ratio of the
// area element sqrt(g) at its nodes to its largest, and the smallest angle (degrees) between
// the two parametric tangents at any node.
struct ElementQuality {
  double min_jacobian_ratio = 1;
  double min_angle_deg = 90;
};
ElementQuality element_quality(const Mesh& mesh, const Matrix3Xd& x);

}  // namespace capflow::geometry
