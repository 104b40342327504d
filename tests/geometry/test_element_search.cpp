// geometry/element_search: the minimum of a quadratic of position over one element, on a patch
// that the element represents exactly (a paraboloid of degree 2 < nb in the parameters): the
// optimality conditions at the result and a dense sampling of the element as the reference.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/element_search.h"
#include "geometry/mesh.h"
#include "geometry/surface.h"

using namespace capflow::geometry;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

namespace {

Vector3d patch(double s, double t) {
  return Vector3d(s, 0.8 * t, 0.3 * s * s - 0.2 * t * t + 0.1 * s * t);
}

// Every element of a NE=6 NB=6 mesh carries the paraboloid patch in its own parameters.
Matrix3Xd patch_surface(const Mesh& mesh) {
  const int nb = mesh.nb();
  Matrix3Xd x(3, mesh.num_local());
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i)
        x.col(mesh.local(e, i, j)) = patch(mesh.nodes()[i], mesh.nodes()[j]);
  return x;
}

// The smallest psi over a 2001 x 2001 grid of the square (an upper bound of the minimum, within
// ~1e-7 of it for these smooth functions).
double sampled_minimum(const QuadraticOfPosition& psi) {
  double best = 1e300;
  for (int b = 0; b <= 2000; ++b)
    for (int a = 0; a <= 2000; ++a)
      best = std::min(best, psi.value(patch(-1.0 + a * 1e-3, -1.0 + b * 1e-3)));
  return best;
}

// Projected gradient of psi(x(s, t)) at the result: zero in a free coordinate, pointing out of
// the square in a coordinate held on its boundary.
void expect_optimal(const ElementMinimum& m, const QuadraticOfPosition& psi) {
  const Vector3d g = psi.grad(m.p.x);
  const double gs = g.dot(m.p.xs), gt = g.dot(m.p.xt);
  auto check = [](double c, double gc) {
    if (c >= 1.0 - 1e-14)
      EXPECT_LE(gc, 1e-10);
    else if (c <= -1.0 + 1e-14)
      EXPECT_GE(gc, -1e-10);
    else
      EXPECT_NEAR(gc, 0.0, 1e-10);
  };
  check(m.s, gs);
  check(m.t, gt);
}

}  // namespace

TEST(ElementSearch, NearestFarthestAndHighestPointsOfAPatch) {
  const Mesh mesh(6, 6);
  const Matrix3Xd x = patch_surface(mesh);
  const ElementEvaluator ev(mesh, x);
  const QuadraticOfPosition cases[] = {
      {1.0, Vector3d(0.2, -0.1, 1.0), Vector3d::Zero()},   // nearest point, interior
      {1.0, Vector3d(3.0, 0.2, 0.5), Vector3d::Zero()},    // nearest point on the edge s = 1
      {1.0, Vector3d(2.5, -2.0, 0.0), Vector3d::Zero()},   // nearest point at a corner
      {-1.0, Vector3d(0.1, 0.0, 0.2), Vector3d::Zero()},   // farthest point (a corner)
      {0.0, Vector3d::Zero(), Vector3d(0.1, 0.05, -1.0)},  // highest point (interior)
  };
  for (const auto& psi : cases) {
    const double sampled = sampled_minimum(psi);
    // From several starts, including corners: each result is a local minimum; for the nearest
    // point (a > 0: one minimum on this patch) each is the global one, for the farthest and the
    // highest point (local minima on the boundary) the best of the starts is.
    double best = 1e300;
    for (const auto& st :
         {std::pair{0.0, 0.0}, std::pair{-1.0, 1.0}, std::pair{0.7, -0.9}, std::pair{0.9, 0.9}}) {
      const ElementMinimum m = minimise_on_element(ev, psi, 2, st.first, st.second);
      EXPECT_NEAR(m.value, psi.value(patch(m.s, m.t)), 1e-13);
      EXPECT_GE(m.value, sampled - 1e-5);
      if (psi.a > 0.0) {
        EXPECT_LE(m.value, sampled + 1e-13);
      }
      expect_optimal(m, psi);
      best = std::min(best, m.value);
    }
    EXPECT_LE(best, sampled + 1e-13);
  }
}

TEST(ElementSearch, NearestPointStartsAtTheNearestNode) {
  const Mesh mesh(6, 6);
  const Matrix3Xd x = patch_surface(mesh);
  const Vector3d x0(0.45, 0.3, -0.6);
  const NearestPoint np = nearest_point(mesh, x, 4, x0);
  QuadraticOfPosition psi;
  psi.c = x0;
  EXPECT_NEAR(np.h, std::sqrt(2.0 * sampled_minimum(psi)), 1e-6);
  EXPECT_NEAR(np.h, (patch(np.s, np.t) - x0).norm(), 1e-13);
  // the segment to x0 is normal to the surface there
  const Vector3d r = patch(np.s, np.t) - x0;
  EXPECT_NEAR(r.dot(np.xs) / r.norm() / np.xs.norm(), 0.0, 1e-10);
  EXPECT_NEAR(r.dot(np.xt) / r.norm() / np.xt.norm(), 0.0, 1e-10);
}
