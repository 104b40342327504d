// First-order membrane smoothing: identity on C1 data, removes cross-edge slope jumps,
// keeps coincident nodes identical.
#include <gtest/gtest.h>

#include <random>

#include "geometry/smoothing.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"

using namespace capflow::geometry;

namespace {
// Per-element perturbation that vanishes on the element edges (keeps C0, breaks C1):
// eps * (1 - xi^2)(1 - eta^2) * random vector per element.
Matrix3Xd kink(const Mesh& mesh, double eps, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Matrix3Xd p = Matrix3Xd::Zero(3, mesh.num_local());
  const int nb = mesh.nb();
  for (int e = 0; e < mesh.ne(); ++e) {
    const Vector3d v(g(rng), g(rng), g(rng));
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        const double s = mesh.nodes()[i], t = mesh.nodes()[j];
        p.col(mesh.local(e, i, j)) = eps * (1 - s * s) * (1 - t * t) * v;
      }
  }
  return p;
}
}  // namespace

TEST(Smoothing, IdentityOnSmoothSurfaceUpToDiscretisation) {
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 12);
    const SmoothingBasis basis = tangent_basis(mesh, mesh.reference());
    Matrix3Xd x = map_points(mesh.reference(), ellipsoid_map(1.5, 0.8, 1.1));
    const Matrix3Xd x0 = x;
    smooth_first_order(mesh, basis, &x);
    // The mapped sphere is C1 only to discretisation accuracy at NB=12 (~1e-6).
    EXPECT_LT((x - x0).cwiseAbs().maxCoeff(), 1e-5) << ne;
  }
}

TEST(Smoothing, ExactIdentityOnGloballyPolynomialField) {
  // A field that is a low-degree polynomial of position restricted to the sphere is not a
  // polynomial in (xi, eta); but a field constant in space is exactly C1 everywhere.
  const Mesh mesh(10, 9);
  const SmoothingBasis basis = tangent_basis(mesh, mesh.reference());
  Matrix3Xd f = Matrix3Xd::Zero(3, mesh.num_local());
  f.row(0).setConstant(2.5);
  f.row(2).setConstant(-1.0);
  const Matrix3Xd f0 = f;
  smooth_first_order(mesh, basis, &f);
  EXPECT_LT((f - f0).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(Smoothing, RemovesCrossEdgeSlopeJumps) {
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 12);
    const SmoothingBasis basis = tangent_basis(mesh, mesh.reference());
    Matrix3Xd x = mesh.reference() + kink(mesh, 1e-3, 42 + ne);
    const double before = max_gradient_jump(mesh, basis, x);
    smooth_first_order(mesh, basis, &x);
    const double after = max_gradient_jump(mesh, basis, x);
    EXPECT_GT(before, 1e-3);
    // One application removes most of the jump; the remainder (near corners, where the
    // prescribed slopes are incompatible with fixed edges) shrinks with every application.
    EXPECT_LT(after, before / 20) << "ne=" << ne << " before=" << before << " after=" << after;
    for (int k = 1; k < 20; ++k) smooth_first_order(mesh, basis, &x);
    const double after20 = max_gradient_jump(mesh, basis, x);
    EXPECT_LT(after20, before / 1000) << "ne=" << ne << " after 20: " << after20;
    // Shared nodes are bit-identical.
    for (const auto& cls : mesh.classes())
      for (int m : cls) ASSERT_EQ((x.col(m) - x.col(cls[0])).norm(), 0.0);
  }
}

TEST(Smoothing, InteriorValuesAwayFromEdgesAreKept) {
  const Mesh mesh(6, 12);
  const SmoothingBasis basis = tangent_basis(mesh, mesh.reference());
  Matrix3Xd x = mesh.reference() + kink(mesh, 1e-3, 5);
  const Matrix3Xd x0 = x;
  smooth_first_order(mesh, basis, &x);
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 2; j < 10; ++j)
      for (int i = 2; i < 10; ++i)
        ASSERT_EQ((x.col(mesh.local(e, i, j)) - x0.col(mesh.local(e, i, j))).norm(), 0.0);
}

TEST(HermiteSmoothing, SharedNodesGetOneGradientTensorAndNodalValuesStay) {
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 10);
    const SmoothingBasis basis = tangent_basis(mesh, mesh.reference());
    Matrix3Xd x = mesh.reference() + kink(mesh, 1e-3, 7 + ne);
    const Matrix3Xd x0 = x;
    Matrix3Xd t1, t2;
    hermite_derivatives(mesh, basis, x, &t1, &t2);
    EXPECT_EQ((x - x0).norm(), 0.0);
    // The tensor built from the Hermite tangents is the same in every element sharing a node.
    double worst = 0;
    for (const auto& cls : mesh.classes()) {
      if (cls.size() < 2) continue;
      auto tensor = [&](int m) -> Eigen::Matrix3d {
        return basis.upper1.col(m) * t1.col(m).transpose() + basis.upper2.col(m) * t2.col(m).transpose();
      };
      for (size_t k = 1; k < cls.size(); ++k) worst = std::max(worst, (tensor(cls[k]) - tensor(cls[0])).cwiseAbs().maxCoeff());
    }
    // What remains is the mismatch of the reference tangent planes themselves (the nodal
    // sphere is C1 only to discretisation accuracy), far below the jump of the raw data.
    const double before = max_gradient_jump(mesh, basis, x);
    EXPECT_LT(worst, before / 30) << ne << " before " << before;
  }
}

TEST(HermiteSmoothing, ReproducesLagrangeDerivativesOfC1Data) {
  // A constant vector field and the linear field F = x on the (C1) reference sphere: the
  // corrections vanish up to the sphere's own discretisation mismatch.
  const Mesh mesh(10, 12);
  const SmoothingBasis basis = tangent_basis(mesh, mesh.reference());
  Matrix3Xd c = Matrix3Xd::Zero(3, mesh.num_local());
  c.row(1).setConstant(3.0);
  Matrix3Xd d1, d2;
  hermite_derivatives(mesh, basis, c, &d1, &d2);
  EXPECT_LT(d1.cwiseAbs().maxCoeff() + d2.cwiseAbs().maxCoeff(), 1e-12);
  hermite_derivatives(mesh, basis, mesh.reference(), &d1, &d2);
  EXPECT_LT((d1 - basis.lower1).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((d2 - basis.lower2).cwiseAbs().maxCoeff(), 1e-6);
}
