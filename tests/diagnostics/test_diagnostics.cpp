// Diagnostics on shapes with closed-form answers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "diagnostics/diagnostics.h"
#include "geometry/shapes.h"

using namespace capflow::diagnostics;
using namespace capflow::geometry;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST(Diagnostics, UnitSphere) {
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 14);
    const ShapeDiagnostics d = measure_shape(mesh, mesh.reference());
    EXPECT_NEAR(d.area / (4 * kPi), 1, 1e-10);
    EXPECT_NEAR(d.volume / (4 * kPi / 3), 1, 1e-10);
    EXPECT_LT(d.centroid.norm(), 1e-12);
    EXPECT_NEAR(d.L, 1, 1e-9);
    EXPECT_NEAR(d.S, 1, 1e-9);
    EXPECT_NEAR(d.D, 0, 1e-9);
    EXPECT_NEAR(d.edge_curvature, 1, 1e-7);
  }
}

TEST(Diagnostics, EllipsoidAxesExtremaAndEdgeCurvature) {
  const double a = 1.8, b = 0.7, c = 1.0;
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 14);
    const Matrix3Xd x = map_points(mesh.reference(), ellipsoid_map(a, b, c));
    const ShapeDiagnostics d = measure_shape(mesh, x);
    EXPECT_NEAR(d.volume, 4 * kPi / 3 * a * b * c, 1e-9) << ne;
    EXPECT_NEAR(d.L, a, 1e-8) << ne;
    EXPECT_NEAR(d.S, b, 1e-8) << ne;
    EXPECT_NEAR(d.W, c, 1e-8) << ne;
    EXPECT_NEAR(d.D, (a - b) / (a + b), 1e-8);
    EXPECT_NEAR(d.Lc, a, 1e-8) << ne;
    EXPECT_NEAR(d.Sc, b, 1e-8) << ne;
    EXPECT_NEAR(d.Wc, c, 1e-8) << ne;
    EXPECT_NEAR(d.edge_curvature, a / (b * b), 1e-7) << ne;
    EXPECT_NEAR(d.tip.x(), a, 1e-9);
  }
}

TEST(Diagnostics, TranslatedAndRotatedEllipsoidInShearAxes) {
  // An ellipsoid rotated by 25 degrees about y and shifted: centroid, axes and inclination.
  const double ang = 25.0 * kPi / 180.0, a = 1.5, b = 0.8, c = 0.9;
  const Vector3d shift(0.3, -0.2, 0.1);
  const Mesh mesh(10, 14);
  const Matrix3Xd x = map_points(mesh.reference(), [&](const Vector3d& p) -> Vector3d {
    const Vector3d q(a * p.x(), c * p.y(), b * p.z());  // long along x, short along z
    return Vector3d(std::cos(ang) * q.x() - std::sin(ang) * q.z(), q.y(),
                    std::sin(ang) * q.x() + std::cos(ang) * q.z()) +
           shift;
  });
  ShapeOptions opt;
  opt.axes = AxesMode::Shear;
  opt.edge_curvature = false;
  const ShapeDiagnostics d = measure_shape(mesh, x, opt);
  EXPECT_LT((d.centroid - shift).norm(), 1e-10);
  EXPECT_NEAR(d.L, a, 1e-8);
  EXPECT_NEAR(d.S, b, 1e-8);
  EXPECT_NEAR(d.W, c, 1e-8);
  EXPECT_NEAR(d.inclination_deg, 25.0, 1e-6);
  EXPECT_NEAR(d.Lc, a, 1e-8);
  EXPECT_NEAR(d.Sc, b, 1e-8);
}

TEST(Diagnostics, EdgeCurvatureOfRandomlyRotatedEllipsoids) {
  // The +x axis through the centroid crosses an ellipsoid x^T Q x = 1 at r = Q_xx^-1/2, where
  // the normal curvature along the unit tangent u is u^T Q u / |Q p|. Random orientations put
  // the crossing anywhere on the elements, also just across an edge from the node closest to
  // the axis (before the search tried every element, 1 in 300 of these cases threw).
  const double a = 1.64, b = 0.51, c = 1.19;  // the NH Ca = 0.6 shear state's axes
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  ShapeOptions opt;
  opt.extrema = false;
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 12);
    for (int k = 0; k < 300; ++k) {
      const Eigen::Matrix3d r =
          Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng))
              .normalized()
              .toRotationMatrix();
      const Matrix3Xd x = map_points(mesh.reference(), [&](const Vector3d& p) -> Vector3d {
        return r * Vector3d(a * p.x(), b * p.y(), c * p.z());
      });
      const Eigen::Matrix3d q =
          r * Vector3d(1 / (a * a), 1 / (b * b), 1 / (c * c)).asDiagonal() * r.transpose();
      const Vector3d p(1 / std::sqrt(q(0, 0)), 0, 0);
      const Vector3d n = (q * p).normalized();
      const Vector3d u = (Vector3d::UnitY() - n.y() * n).normalized();
      const double kappa = u.dot(q * u) / (q * p).norm();
      const ShapeDiagnostics d = measure_shape(mesh, x, opt);
      ASSERT_TRUE(std::isfinite(d.edge_curvature)) << "ne " << ne << " rotation " << k;
      EXPECT_NEAR(d.edge_curvature / kappa, 1, 1e-4) << "ne " << ne << " rotation " << k;
      EXPECT_NEAR(d.tip.x(), p.x(), 1e-7) << "ne " << ne << " rotation " << k;
    }
  }
}

TEST(Diagnostics, EdgeCurvatureIsNaNWhereTheAxisMissesTheBody) {
  // A thin tube bent into a C that opens towards +x: its centroid lies in the hollow and the
  // +x axis through it leaves between the tube's ends, crossing no element.
  const Mesh mesh(6, 10);
  const Matrix3Xd x = map_points(mesh.reference(), [](const Vector3d& p) -> Vector3d {
    const double r = 0.2 * p.x(), phi = 2.0 * p.y();  // across and along the tube
    return Vector3d(1.0 - (1.0 - r) * std::cos(phi), (1.0 - r) * std::sin(phi), 0.2 * p.z());
  });
  ShapeOptions opt;
  opt.extrema = false;
  const ShapeDiagnostics d = measure_shape(mesh, x, opt);
  EXPECT_GT(d.centroid.x(), 0.3);  // in the hollow: the tube's middle is at x = 0
  EXPECT_TRUE(std::isnan(d.edge_curvature));
  EXPECT_EQ(d.tip, d.centroid);
}

TEST(Diagnostics, CrossSectionsLieOnTheEllipse) {
  const double a = 1.8, b = 0.7, c = 1.0;
  const Mesh mesh(14, 12);
  const Matrix3Xd x = map_points(mesh.reference(), ellipsoid_map(a, b, c));
  const auto z0 = cross_section(mesh, x, 2, 0.0);
  const auto y0 = cross_section(mesh, x, 1, 0.0);
  ASSERT_GT(z0.size(), 100u);
  ASSERT_GT(y0.size(), 100u);
  double err = 0, prev = -10;
  for (const auto& p : z0) {
    err = std::max(err, std::abs(std::hypot(p.x() / a, p.y() / b) - 1));
    const double th = std::atan2(p.y(), p.x());
    EXPECT_GE(th, prev);  // ordered by angle
    prev = th;
  }
  for (const auto& p : y0) err = std::max(err, std::abs(std::hypot(p.x() / a, p.y() / c) - 1));
  EXPECT_LT(err, 1e-6);
  // Largest angular gap is small: the section goes all the way round.
  double gap = 0;
  for (size_t k = 1; k < z0.size(); ++k)
    gap =
        std::max(gap, std::atan2(z0[k].y(), z0[k].x()) - std::atan2(z0[k - 1].y(), z0[k - 1].x()));
  EXPECT_LT(gap, 0.2);
}

TEST(Diagnostics, ExtremaOnElementEdgesAreFound) {
  // NE=10 puts the y-extremum of this shape on the x = 0 division line (an element edge);
  // a tilted ellipsoid moves Lc off every node.
  const Mesh mesh(10, 10);
  const Matrix3Xd x = map_points(mesh.reference(), [](const Vector3d& p) -> Vector3d {
    return Vector3d(1.4 * p.x() + 0.2 * p.y(), 0.9 * p.y(), 1.1 * p.z());
  });
  const ShapeDiagnostics d = measure_shape(mesh, x);
  // Brute force over a fine parameter grid on every element.
  const ElementEvaluator ev(mesh, x);
  double lc = 0, sc = 1e9;
  for (int e = 0; e < mesh.ne(); ++e)
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j <= 200; ++j) {
        const double r = (ev.eval(e, -1 + i / 100.0, -1 + j / 100.0).x - d.centroid).norm();
        lc = std::max(lc, r);
        sc = std::min(sc, r);
      }
  EXPECT_GE(d.Lc, lc - 1e-12);
  EXPECT_LT(d.Lc - lc, 1e-4);
  EXPECT_LE(d.Sc, sc + 1e-12);
  EXPECT_LT(sc - d.Sc, 1e-4);
}
