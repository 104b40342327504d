#include "geometry/shapes.h"

#include <cmath>

namespace capflow::geometry {

Matrix3Xd map_points(const Matrix3Xd& reference, const PointMap& f) {
  Matrix3Xd out(3, reference.cols());
  for (int m = 0; m < reference.cols(); ++m) out.col(m) = f(reference.col(m));
  return out;
}

PointMap ellipsoid_map(double a, double b, double c) {
  return [=](const Vector3d& p) { return Vector3d(a * p.x(), b * p.y(), c * p.z()); };
}

PointMap lamellar_map(double a, double b, double c, double p) {
  return [=](const Vector3d& q) {
    return Vector3d(a * q.x(), b * q.y() * (1.0 - p * q.x() * q.x()), c * q.z());
  };
}

double ellipsoid_mean_curvature(double a, double b, double c, const Vector3d& x) {
  const double a2 = a * a, b2 = b * b, c2 = c * c;
  const double h = 1.0 / std::sqrt(x.x() * x.x() / (a2 * a2) + x.y() * x.y() / (b2 * b2) +
                                    x.z() * x.z() / (c2 * c2));
  return h * h * h * (a2 + b2 + c2 - x.squaredNorm()) / (2.0 * a2 * b2 * c2);
}

}  // namespace capflow::geometry
