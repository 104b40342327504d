#include "geometry/reference_shape.h"

#include <algorithm>
#include <cmath>

#include "geometry/surface.h"

namespace capflow::geometry {

const char* shape_name(ReferenceShape::Kind k) {
  switch (k) {
    case ReferenceShape::Kind::Sphere:
      return "sphere";
    case ReferenceShape::Kind::Spheroid:
      return "spheroid";
    case ReferenceShape::Kind::Biconcave:
      return "biconcave";
  }
  return "";
}

AxisymmetricProfile profile_of(const ReferenceShape& s) {
  switch (s.kind) {
    case ReferenceShape::Kind::Sphere:
      return spheroid_profile(1, 1);
    case ReferenceShape::Kind::Spheroid:
      return scaled_to_unit_volume(spheroid_profile(1, s.aspect));
    case ReferenceShape::Kind::Biconcave:
      return scaled_to_unit_volume(evans_fung_profile());
  }
  return {};
}

PointMap reference_shape_map(const ReferenceShape& s) {
  if (s.is_sphere()) return [](const Vector3d& X) { return X; };
  const AxisymmetricProfile p = profile_of(s);
  const double R = static_cast<double>(p.R * p.scale), k = static_cast<double>(p.scale);
  const double q0 = static_cast<double>(p.q0), q1 = static_cast<double>(p.q1),
               q2 = static_cast<double>(p.q2);
  const int ax = s.axis;
  return [=](const Vector3d& X) {
    const double rho2 = X.squaredNorm() - X[ax] * X[ax];
    Vector3d y = R * X;
    y[ax] = k * X[ax] * (q0 + q1 * rho2 + q2 * rho2 * rho2);
    return y;
  };
}

Matrix3Xd reference_positions(const Mesh& mesh, const ReferenceShape& s) {
  if (s.is_sphere()) return mesh.reference();
  return map_points(mesh.reference(), reference_shape_map(s));
}

long double theta_of(const ReferenceShape& s, const Vector3d& X) {
  const long double a = std::fabs(static_cast<long double>(X[s.axis]));
  long double rho2 = 0;
  for (int k = 0; k < 3; ++k)
    if (k != s.axis) rho2 += static_cast<long double>(X[k]) * X[k];
  return std::atan2(std::sqrt(rho2), a);
}

ElementQuality element_quality(const Mesh& mesh, const Matrix3Xd& x) {
  const SurfaceGeometry g = compute_geometry(mesh, x);
  ElementQuality q;
  const int per = mesh.nodes_per_element();
  for (int e = 0; e < mesh.ne(); ++e) {
    double lo = INFINITY, hi = 0;
    for (int k = e * per; k < (e + 1) * per; ++k) {
      lo = std::min(lo, g.jac[k]);
      hi = std::max(hi, g.jac[k]);
      const double c = std::abs(g.t1.col(k).normalized().dot(g.t2.col(k).normalized()));
      q.min_angle_deg = std::min(q.min_angle_deg, std::acos(std::min(1.0, c)) * 180 / M_PI);
    }
    q.min_jacobian_ratio = std::min(q.min_jacobian_ratio, lo / hi);
  }
  return q;
}

}  // namespace capflow::geometry
