// Spectral upsampling (CPU): the interpolant reproduces the surface, normals come from its
// derivatives, and element edges are seamless.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "render/upsample.h"

namespace capflow::render {
namespace {

Snapshot make(int ne, int nb, const geometry::PointMap& map) {
  geometry::Mesh mesh(ne, nb);
  const auto x = geometry::map_points(mesh.reference(), map);
  Snapshot s;
  s.ne = ne;
  s.nb = nb;
  s.x.resize(3 * static_cast<size_t>(mesh.num_local()));
  s.tau1.resize(mesh.num_local());
  s.tau2.resize(mesh.num_local());
  for (int k = 0; k < mesh.num_local(); ++k) {
    for (int d = 0; d < 3; ++d) s.x[3 * k + d] = x(d, k);
    s.tau1[k] = x(0, k) * x(0, k) + 2;  // a smooth field: x^2 + 2 and y
    s.tau2[k] = x(1, k);
  }
  return s;
}

TEST(Upsample, EllipsoidPointsNormalsAndFieldAreAccurate) {
  const double a = 1.8, b = 0.7, c = 1.0;
  for (int ne : {6, 10, 14}) {
    const Snapshot s = make(ne, 14, geometry::ellipsoid_map(a, b, c));
    SurfaceMesh m;
    Upsampler(14, 25).build(s, ColorField::MaxTension, &m);
    ASSERT_EQ(m.num_vertices(), ne * 25 * 25);
    ASSERT_EQ(m.triangles.size(), static_cast<size_t>(ne) * 24 * 24 * 2 * 3);
    double max_level = 0, max_angle = 0, max_field = 0;
    for (int v = 0; v < m.num_vertices(); ++v) {
      const double x = m.position[3 * v], y = m.position[3 * v + 1], z = m.position[3 * v + 2];
      max_level = std::max(max_level, std::abs(x * x / (a * a) + y * y / (b * b) + z * z / (c * c) - 1));
      double g[3] = {x / (a * a), y / (b * b), z / (c * c)};
      const double gl = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      double dot = 0;
      for (int d = 0; d < 3; ++d) dot += g[d] / gl * m.normal[3 * v + d];
      max_angle = std::max(max_angle, std::acos(std::min(1.0, dot)));
      max_field = std::max(max_field, std::abs(m.value[v] - (x * x + 2)));
    }
    EXPECT_LT(max_level, 2e-4) << "ne=" << ne;
    EXPECT_LT(max_angle, 2e-3) << "ne=" << ne;  // radians, outward
    EXPECT_LT(max_field, 1e-3) << "ne=" << ne;
    EXPECT_NEAR(m.value_min, 2.0, 1e-3);
    EXPECT_NEAR(m.value_max, 2 + a * a, 1e-3);
  }
}

TEST(Upsample, ElementEdgesAreWelded) {
  // Every grid point on an element boundary coincides with at least one point of another
  // element, with the same position, normal and value (no seam).
  const Snapshot s = make(10, 8, geometry::lamellar_map());
  SurfaceMesh m;
  Upsampler(8, 25).build(s, ColorField::MinTension, &m);
  const int n = 25;
  int checked = 0;
  for (int e = 0; e < s.ne; ++e)
    for (int a = 0; a < n; a += n - 1)
      for (int b = 0; b < n; ++b) {
        const int v = (e * n + b) * n + a;
        int partners = 0;
        for (int w = 0; w < m.num_vertices(); ++w) {
          if (w / (n * n) == e) continue;
          double d2 = 0;
          for (int k = 0; k < 3; ++k) d2 += std::pow(m.position[3 * v + k] - m.position[3 * w + k], 2);
          if (d2 > 1e-20) continue;
          ++partners;
          for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normal[3 * v + k], m.normal[3 * w + k]);
          EXPECT_EQ(m.value[v], m.value[w]);
        }
        EXPECT_GE(partners, 1) << "e=" << e << " a=" << a << " b=" << b;
        ++checked;
      }
  EXPECT_EQ(checked, 10 * 2 * n);
}

TEST(Upsample, ExactForPolynomialOfDegreeNbMinusOne) {
  // A field that is a polynomial of degree nb-1 in (xi, eta) is reproduced exactly at every
  // grid point: build it on the reference parameters directly.
  const int nb = 5, n = 7;
  Snapshot s;
  s.ne = 1;
  s.nb = nb;
  geometry::Mesh mesh(6, nb);
  const auto& xi = mesh.nodes();
  s.x.resize(3 * nb * nb);
  s.tau1.resize(nb * nb);
  s.tau2.resize(nb * nb);
  auto f = [](double p, double q) { return std::pow(p, 4) - 2 * p * q * q * q + 0.5 * q; };
  for (int j = 0; j < nb; ++j)
    for (int i = 0; i < nb; ++i) {
      const int k = j * nb + i;
      s.x[3 * k] = xi[i];
      s.x[3 * k + 1] = xi[j];
      s.x[3 * k + 2] = 0;
      s.tau1[k] = s.tau2[k] = f(xi[i], xi[j]);
    }
  SurfaceMesh m;
  Upsampler(nb, n).build(s, ColorField::MeanTension, &m);
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const int v = b * n + a;
      const double p = -1 + 2.0 * a / (n - 1), q = -1 + 2.0 * b / (n - 1);
      EXPECT_NEAR(m.position[3 * v], p, 1e-6);
      EXPECT_NEAR(m.position[3 * v + 1], q, 1e-6);
      EXPECT_NEAR(m.value[v], f(p, q), 1e-5);
      EXPECT_NEAR(m.normal[3 * v + 2], 1.0, 1e-6);  // x_s x x_t = +z
    }
}

TEST(Upsample, BendingFieldIsTheSnapshotsBendingArray) {
  // ColorField::BendingEnergy colours by the snapshot's bending array; without one (a capsule
  // with no bending), by zero; an array of another size is refused.
  Snapshot s = make(6, 5, geometry::ellipsoid_map(1, 1, 1));
  EXPECT_EQ(nodal_field(s, ColorField::BendingEnergy), std::vector<double>(s.tau1.size(), 0.0));
  s.bending = s.tau1;
  EXPECT_EQ(nodal_field(s, ColorField::BendingEnergy), s.tau1);
  SurfaceMesh m;
  Upsampler(5, 9).build(s, ColorField::BendingEnergy, &m);
  Upsampler(5, 9).build(s, ColorField::MaxTension, &m);
  s.bending.pop_back();
  EXPECT_THROW(Upsampler(5, 9).build(s, ColorField::BendingEnergy, &m), std::invalid_argument);
}

TEST(Upsample, RejectsInconsistentSnapshot) {
  Snapshot s = make(6, 6, geometry::ellipsoid_map(1, 1, 1));
  s.x.pop_back();
  SurfaceMesh m;
  EXPECT_THROW(Upsampler(6, 25).build(s, ColorField::MaxTension, &m), std::invalid_argument);
}

}  // namespace
}  // namespace capflow::render
