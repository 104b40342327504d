// capflow/geometry/shapes: analytic maps applied to the reference sphere nodes, to build test
// and demonstration surfaces (the nodes of the mapped surface are the mapped sphere nodes;
// the surface in between is their Lagrange interpolant).
#pragma once

#include <functional>
#include <string>

#include "geometry/mesh.h"

namespace capflow::geometry {

using PointMap = std::function<Vector3d(const Vector3d&)>;

Matrix3Xd map_points(const Matrix3Xd& reference, const PointMap& f);

// Ellipsoid with semi-axes (a, b, c) along x, y, z: X -> (a X, b Y, c Z).
PointMap ellipsoid_map(double a, double b, double c);

// A strongly flattened "lamellar" shape like the neo-Hookean capsule at high Ca (long in x,
// thin in y with a flat middle, pointed edges at +-x):
//   x = a X,  y = b Y (1 - p X^2),  z = c Z.   Default a=2.6, b=0.45, c=1.0, p=0.6.
PointMap lamellar_map(double a = 2.6, double b = 0.45, double c = 1.0, double p = 0.6);

// Exact mean curvature (H = +1/R convention) of the ellipsoid (a, b, c) at a point on it:
//   H = h^3 (a^2 + b^2 + c^2 - |x|^2) / (2 a^2 b^2 c^2),  h = (x^2/a^4 + y^2/b^4 + z^2/c^4)^-1/2.
double ellipsoid_mean_curvature(double a, double b, double c, const Vector3d& x);

}  // namespace capflow::geometry
