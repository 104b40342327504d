// geometry/axisymmetric and geometry/reference_shape: the 1-D profiles against closed forms and
// published figures, then the spectral mesh's area, volume and mean curvature of the reference
// shapes against the profiles, converging exponentially in NB.
#include <gtest/gtest.h>

#include <cmath>

#include "diagnostics/diagnostics.h"
#include "geometry/axisymmetric.h"
#include "geometry/reference_shape.h"
#include "geometry/surface.h"

namespace capflow::geometry {
namespace {

TEST(AxisymmetricProfile, TheUnitSphere) {
  const AxisymmetricProfile p = spheroid_profile(1, 1);
  EXPECT_NEAR(static_cast<double>(profile_area(p)), 4 * M_PI, 1e-15);
  EXPECT_NEAR(static_cast<double>(profile_volume(p)), 4 * M_PI / 3, 1e-15);
  for (long double th : {0.0L, 0.3L, 1.0L, 1.5707963267948966L}) {
    const ProfilePoint q = profile_point(p, th);
    EXPECT_NEAR(static_cast<double>(q.H), 1, 1e-15);
    EXPECT_NEAR(static_cast<double>(q.K), 1, 1e-15);
  }
}

// Spheroid area in closed form (equatorial a, polar c).
double spheroid_area(double a, double c) {
  if (c < a) {
    const double e = std::sqrt(1 - c * c / (a * a));
    return 2 * M_PI * a * a * (1 + (1 - e * e) / e * std::atanh(e));
  }
  const double e = std::sqrt(1 - a * a / (c * c));
  return 2 * M_PI * a * a * (1 + c / (a * e) * std::asin(e));
}

TEST(AxisymmetricProfile, SpheroidsAgainstClosedForms) {
  for (double r : {0.3, 0.5, 2.0, 3.0}) {
    const AxisymmetricProfile p = scaled_to_unit_volume(spheroid_profile(1, r));
    const double a = static_cast<double>(p.scale), c = r * a;
    EXPECT_NEAR(static_cast<double>(profile_volume(p)), 4 * M_PI / 3, 1e-14) << r;
    EXPECT_NEAR(static_cast<double>(profile_area(p)), spheroid_area(a, c), 1e-13) << r;
    for (long double th : {0.0L, 0.4L, 0.9L, 1.5L}) {
      const ProfilePoint q = profile_point(p, th);
      const Vector3d x(static_cast<double>(q.r), 0, static_cast<double>(q.z));
      EXPECT_NEAR(static_cast<double>(q.H), ellipsoid_mean_curvature(a, a, c, x), 1e-12)
          << r << " " << static_cast<double>(th);
      // K of a spheroid: c^2 / (a^2 c^2 (x^2 + y^2)/a^4 + z^2/c^4)^2 / a^2 ... via h: K = h^4/(a^4 c^2)
      const double h = 1 / std::sqrt(x[0] * x[0] / std::pow(a, 4) + x[2] * x[2] / std::pow(c, 4));
      EXPECT_NEAR(static_cast<double>(q.K), std::pow(h, 4) / (a * a * a * a * c * c), 1e-11);
    }
  }
}

TEST(AxisymmetricProfile, EvansFungAsPublished) {
  // method.md sec. 10: a = 2.8215 um, V = 94.09 um^3, A = 134.09 um^2 (30-digit quadrature).
  const AxisymmetricProfile p = evans_fung_profile();
  EXPECT_NEAR(static_cast<double>(equal_volume_radius(p)), 2.8215, 5e-5);
  EXPECT_NEAR(static_cast<double>(profile_volume(p)), 94.09, 5e-3);
  EXPECT_NEAR(static_cast<double>(profile_area(p)), 134.09, 5e-3);
  // The quadrature has converged at the default 48 points: twice as many agree to 1e-16.
  EXPECT_LT(std::fabs(profile_area(p, 48) - profile_area(p, 96)), 1e-16L * 134);
  EXPECT_LT(std::fabs(profile_volume(p, 48) - profile_volume(p, 96)), 1e-16L * 94);
  // ... and it converges exponentially: 24 points 4e-9 away, 32 points 2e-12.
  EXPECT_GT(std::fabs(profile_area(p, 24) - profile_area(p, 96)), 1e-10L);
}

TEST(ReferenceShape, TheSphereIsTheMeshReferenceBitForBit) {
  const Mesh mesh(6, 8);
  const Matrix3Xd x = reference_positions(mesh, {});
  EXPECT_EQ((x - mesh.reference()).cwiseAbs().maxCoeff(), 0.0);
}

TEST(ReferenceShape, KeepsTheMirrorPlanes) {
  const Mesh mesh(10, 8);
  for (int axis = 0; axis < 3; ++axis) {
    ReferenceShape s;
    s.kind = ReferenceShape::Kind::Biconcave;
    s.axis = axis;
    const Matrix3Xd x = reference_positions(mesh, s);
    for (int k = 0; k < 3; ++k)
      for (int m = 0; m < mesh.num_local(); ++m) {
        Vector3d y = x.col(m);
        y[k] = -y[k];
        EXPECT_LT((x.col(mesh.mirror(k)[m]) - y).norm(), 1e-14);
      }
  }
}

struct Errors {
  double area, volume, H;
};

Errors errors(const ReferenceShape& s, int ne, int nb) {
  const Mesh mesh(ne, nb);
  const Matrix3Xd x = reference_positions(mesh, s);
  const AxisymmetricProfile p = profile_of(s);
  const diagnostics::ShapeDiagnostics d = diagnostics::measure_shape(mesh, x);
  const SurfaceGeometry g = compute_geometry(mesh, x);
  Errors e{std::abs(d.area - static_cast<double>(profile_area(p))),
           std::abs(d.volume - static_cast<double>(profile_volume(p))), 0};
  for (int m = 0; m < mesh.num_local(); ++m)
    e.H = std::max(e.H, static_cast<double>(std::fabs(
                            g.mean_curvature[m] -
                            profile_point(p, theta_of(s, mesh.reference().col(m))).H)));
  return e;
}

TEST(ReferenceShape, TheMeshConvergesExponentiallyToTheProfile) {
  ReferenceShape bic;
  bic.kind = ReferenceShape::Kind::Biconcave;
  ReferenceShape oblate;
  oblate.kind = ReferenceShape::Kind::Spheroid;
  oblate.aspect = 0.5;
  ReferenceShape prolate = oblate;
  prolate.aspect = 2.0;
  prolate.axis = 0;
  for (const ReferenceShape& s : {bic, oblate, prolate})
    for (int ne : {6, 10}) {
      const Errors e8 = errors(s, ne, 8), e12 = errors(s, ne, 12), e16 = errors(s, ne, 16);
      const std::string what = std::string(shape_name(s.kind)) + " NE=" + std::to_string(ne);
      // The nodal mean curvature (second derivatives at edges and corners included): at least
      // a factor 30 per 4 more nodes, a straight line on a log scale.
      EXPECT_LT(e12.H, e8.H / 30) << what;
      EXPECT_LT(e16.H, e12.H / 30) << what;
      EXPECT_LT(e16.H, 1e-4) << what;
      EXPECT_LT(e12.volume, 1e-9) << what;
      EXPECT_LT(e16.area, 1e-8) << what;
      EXPECT_LT(e12.area, e8.area) << what;
    }
}

TEST(ReferenceShape, ElementQualityIsBounded) {
  ReferenceShape s;
  s.kind = ReferenceShape::Kind::Biconcave;
  const Mesh mesh(6, 12);
  const ElementQuality q = element_quality(mesh, reference_positions(mesh, s));
  EXPECT_GT(q.min_jacobian_ratio, 0.4);
  EXPECT_GT(q.min_angle_deg, 40);
  const ElementQuality sphere = element_quality(mesh, mesh.reference());
  EXPECT_NEAR(sphere.min_angle_deg, 60, 0.5) << "the cube's corners on the sphere";
}

}  // namespace
}  // namespace capflow::geometry
