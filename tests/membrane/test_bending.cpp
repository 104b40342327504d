// membrane/bending: the bending load on the sphere (zero, and the uniform load of a spontaneous
// curvature), its linearisation about the sphere (l = 2 and 3, both models), the load on
// spheroids and the red blood cell against the axisymmetric profile (exponential convergence in
// NB), and the load against the derivative of the discrete bending energy (virtual work by
// finite differences) on shapes without symmetry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "geometry/reference_shape.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"
#include "membrane/bending.h"
#include "spectral/spectral.h"

namespace capflow::membrane {
namespace {

using geometry::Mesh;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

BendingOptions helfrich(double kb, double c0 = 0) {
  BendingOptions o;
  o.modulus = kb;
  o.c0 = c0;
  return o;
}

// max |f - f_exact| on the nodal sphere of NE = 6 (the interpolant is a sphere only to the
// discretisation error, and the load takes four derivatives of it).
double sphere_error(int nb, double c0) {
  const Mesh mesh(6, nb);
  const Bending b(mesh, mesh.reference(), helfrich(1, c0));
  const Matrix3Xd f = b.load(mesh.reference());
  double worst = 0;
  for (int k = 0; k < mesh.num_local(); ++k) {
    const Vector3d n = mesh.reference().col(k);
    worst = std::max(worst, (f.col(k) + (2 - c0) * c0 * n).norm());  // f.n = -(2 - c0) c0
  }
  return worst;
}

TEST(Bending, TheSphereConvergesExponentially) {
  // c0 = 0: no load; c0 != 0: the uniform normal load -kb (2 - c0) c0 (H = K = 1).
  for (double c0 : {0.0, -1.0, 0.5, 3.0}) {
    const double e12 = sphere_error(12, c0), e16 = sphere_error(16, c0),
                 e20 = sphere_error(20, c0);
    std::printf("sphere c0 = %g: max |f - f_exact| / kb = %.2e, %.2e, %.2e at NB = 12, 16, 20\n",
                c0, e12, e16, e20);
    EXPECT_LT(e16, e12 / 10) << c0;
    EXPECT_LT(e20, e16 / 10) << c0;
    EXPECT_LT(e20, 1e-4) << c0;
  }
}

// r = 1 + eps Y_l0(z): (f(eps) - f(0)).n / (kb eps Y) -> the linear coefficient (the
// unperturbed nodal sphere's own discretisation error cancels).
double linear_coefficient_error(int l, BendingModel model, double expected, int nb = 16) {
  const Mesh mesh(6, nb);
  const auto Y = [l](double z) {
    return l == 2 ? (3 * z * z - 1) / 2 : (5 * z * z * z - 3 * z) / 2;
  };
  const double eps = 1e-6, kb = 1;
  Matrix3Xd x = mesh.reference();
  for (int k = 0; k < x.cols(); ++k) x.col(k) *= 1 + eps * Y(x(2, k));
  BendingOptions o = helfrich(kb);
  o.model = model;
  const Bending b(mesh, mesh.reference(), o);
  const Matrix3Xd f = b.load(x) - b.load(mesh.reference());
  double worst = 0;
  for (int k = 0; k < x.cols(); ++k) {
    const Vector3d n = mesh.reference().col(k);
    worst = std::max(worst, std::abs(f.col(k).dot(n) - expected * kb * eps * Y(n[2])));
  }
  return worst / (expected * kb * eps);
}

TEST(Bending, LinearisedAboutTheSphere) {
  // method.md sec. 10: (l-1) l (l+1) (l+2) with c0 = 0; (l-1)^2 (l+2)^2 about the sphere's own
  // curvature. Relative to the load's amplitude: O(eps) and the discretisation.
  struct Case {
    int l;
    BendingModel model;
    double coefficient;
  };
  for (const Case& c : {Case{2, BendingModel::Helfrich, 24}, Case{3, BendingModel::Helfrich, 120},
                        Case{2, BendingModel::Reference, 16}, Case{3, BendingModel::Reference, 100}}) {
    const double e12 = linear_coefficient_error(c.l, c.model, c.coefficient, 12);
    const double e16 = linear_coefficient_error(c.l, c.model, c.coefficient, 16);
    std::printf("l = %d, %s: coefficient %g, relative error %.2e (NB 12), %.2e (NB 16)\n", c.l,
                c.model == BendingModel::Helfrich ? "helfrich" : "reference", c.coefficient, e12,
                e16);
    EXPECT_LT(e16, 5e-3) << c.l;
    EXPECT_LT(e16, e12 / 10) << c.l;
  }
}

// max |f.n - f_profile| over the nodes off the poles, Helfrich c0 = 0, for a reference shape,
// relative to max |f_profile| there.
double profile_error(const geometry::ReferenceShape& s, int ne, int nb) {
  const Mesh mesh(ne, nb);
  const Matrix3Xd x = geometry::reference_positions(mesh, s);
  const Bending b(mesh, x, helfrich(1));
  const Matrix3Xd f = b.load(x);
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh, x);
  const geometry::AxisymmetricProfile p = geometry::profile_of(s);
  double worst = 0, size = 0;
  for (int k = 0; k < mesh.num_local(); ++k) {
    const long double th = geometry::theta_of(s, mesh.reference().col(k));
    if (th < 1e-2L || th > 1.5607963L) continue;  // the formula's limits at the pole and rim
    const geometry::ProfilePoint q = geometry::profile_point(p, th);
    const long double expected =
        -2 * (geometry::profile_laplacian_H(p, th) + 2 * q.H * (q.H * q.H - q.K));
    worst = std::max(worst, static_cast<double>(std::fabs(f.col(k).dot(g.n.col(k)) - expected)));
    size = std::max(size, static_cast<double>(std::fabs(expected)));
  }
  return worst / size;
}

TEST(Bending, ConvergesToTheAxisymmetricLoad) {
  geometry::ReferenceShape oblate;
  oblate.kind = geometry::ReferenceShape::Kind::Spheroid;
  oblate.aspect = 0.6;
  geometry::ReferenceShape rbc;
  rbc.kind = geometry::ReferenceShape::Kind::Biconcave;
  for (const auto& s : {oblate, rbc}) {
    const double e12 = profile_error(s, 6, 12), e16 = profile_error(s, 6, 16),
                 e20 = profile_error(s, 6, 20);
    const std::string what = geometry::shape_name(s.kind);
    std::printf("%s: max |f.n - f_profile| / max |f_profile| = %.2e, %.2e, %.2e at NB = 12, 16, 20\n",
                what.c_str(), e12, e16, e20);
    EXPECT_LT(e20, e12 / 5) << what;
    EXPECT_LT(e20, e16) << what;
    EXPECT_LT(e20, 0.03) << what;
  }
}

// INT f.v dA by each element's Gauss-Lobatto nodes, and the central difference of the energy
// along v: their difference relative to their size.
double virtual_work_mismatch(const Mesh& mesh, const Matrix3Xd& x, const Bending& b,
                             const std::function<Vector3d(const Vector3d&)>& v) {
  Matrix3Xd dx(3, x.cols());
  for (int k = 0; k < x.cols(); ++k) dx.col(k) = v(x.col(k));
  const double h = 1e-6;
  const double fd = (b.energy(x + h * dx) - b.energy(x - h * dx)) / (2 * h);
  const Matrix3Xd f = b.load(x);
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh, x);
  const spectral::Rule gl = spectral::gauss_lobatto(mesh.nb());
  const int nb = mesh.nb();
  double work = 0;
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        const int k = (e * nb + j) * nb + i;
        work += gl.w[i] * gl.w[j] * g.jac[k] * f.col(k).dot(dx.col(k));
      }
  return std::abs(work - fd) / std::abs(fd);
}

TEST(Bending, TheLoadIsTheDerivativeOfTheEnergy) {
  // A shape without symmetry and a displacement field without symmetry.
  const geometry::PointMap shape = [](const Vector3d& X) {
    return Vector3d(1.2 * X[0] + 0.1 * X[1] * X[1], 0.9 * X[1] + 0.05 * X[0] * X[2],
                    0.85 * X[2] + 0.08 * X[0] * X[0]);
  };
  const auto v = [](const Vector3d& y) {
    return Vector3d(std::sin(y[1]), std::cos(y[2]) * y[0], y[0] * y[1] + 0.3);
  };
  for (BendingModel model : {BendingModel::Helfrich, BendingModel::Reference}) {
    double previous = 1;
    for (int nb : {8, 12, 16}) {
      const Mesh mesh(6, nb);
      geometry::ReferenceShape rbc;
      rbc.kind = geometry::ReferenceShape::Kind::Biconcave;
      // Helfrich with c0 = 0.7 on the sheared ellipsoid; the reference model bent away from
      // the red blood cell by the same map.
      const Matrix3Xd ref = model == BendingModel::Helfrich
                                ? mesh.reference()
                                : geometry::reference_positions(mesh, rbc);
      const Matrix3Xd x = geometry::map_points(ref, shape);
      BendingOptions o = helfrich(0.01, model == BendingModel::Helfrich ? 0.7 : 0);
      o.model = model;
      const Bending b(mesh, ref, o);
      const double mismatch = virtual_work_mismatch(mesh, x, b, v);
      std::printf("%s: virtual work against the energy's derivative, relative %.2e at NB = %d\n",
                  model == BendingModel::Helfrich ? "helfrich" : "reference", mismatch, nb);
      EXPECT_LT(mismatch, previous) << "NB " << nb;
      previous = mismatch;
      if (nb == 16) {
        EXPECT_LT(mismatch, 1e-3) << static_cast<int>(model);
      }
    }
  }
}

}  // namespace
}  // namespace capflow::membrane
