// The single layer's inner far tier is made only for the elements a target of the call may reach
// (stokes/element_bounds.h within_reach): the bound never says "out of reach" for a point that
// the nearest-point search puts within reach, and which elements' inner tiers a call made changes
// no bit of any target's sum (each target alone, with its own smaller set, gives the same bits
// as the call over all the octant targets).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "geometry/element_search.h"
#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "stokes/boundary_integral.h"
#include "stokes/element_bounds.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

namespace {

Matrix3Xd lamellar(const geometry::Mesh& mesh) {
  return geometry::map_points(mesh.reference(), geometry::lamellar_map(2.0, 0.6, 1.0, 0.3));
}

}  // namespace

// Points scattered around the lamellar shape at NE=6 NB=10 (a node plus a random offset of
// 0.01 .. 1), thresholds 0.05 .. 0.5: wherever within_reach says no, the nearest point of the
// element is at th or beyond. Both answers occur (the check is not vacuous).
TEST(ElementBounds, WithinReachNeverMissesANearerPoint) {
  const geometry::Mesh mesh(6, 10);
  const Matrix3Xd x = lamellar(mesh);
  const int nb = mesh.nb();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), scale(-2.0, 0.0);
  std::uniform_int_distribution<int> node(0, mesh.num_local() - 1);
  int out_of_reach = 0, in_reach = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Vector3d dir(u(rng), u(rng), u(rng));
    const Vector3d p = x.col(node(rng)) + std::pow(10.0, scale(rng)) * dir.normalized();
    for (int e = 0; e < mesh.ne(); ++e) {
      const stokes::ElementBounds b = stokes::element_bounds(x, nb, e);
      int best = 0;
      geometry::nearest_node(mesh, x, e, p, &best);
      const double h = geometry::nearest_point(mesh, x, e, p, best).h;
      for (double th : {0.05, 0.1, 0.2, 0.5}) {
        if (stokes::within_reach(mesh, x, e, b, p, th)) {
          ++in_reach;
        } else {
          ++out_of_reach;
          EXPECT_GE(h, th) << "element " << e << " point " << p.transpose();
        }
      }
    }
  }
  EXPECT_GT(out_of_reach, 1000);
  EXPECT_GT(in_reach, 1000);
}

// The octant targets of the lamellar shape at NE=6 NB=10 and NE=10 NB=12 (box): the call over all
// of them against one call per target (which makes fewer inner tiers), bit for bit; no pair took
// an inner tier the bound had ruled out; the octant call left some out.
TEST(StokesInnerTier, WhichInnerTiersWereMadeChangesNoBit) {
  for (const auto& [ne, nb, division] :
       {std::tuple{6, 10, geometry::Division::Cube}, std::tuple{10, 12, geometry::Division::Box}}) {
    const geometry::Mesh mesh(ne, nb, geometry::ElementMap::Equiangular, division);
    const Matrix3Xd x = lamellar(mesh);
    Matrix3Xd f(3, mesh.num_local());
    for (int m = 0; m < mesh.num_local(); ++m) {
      const Vector3d p = x.col(m);
      f.col(m) = Vector3d(std::sin(p[0] + 0.3), p[1] * p[2] - 0.4, std::exp(0.5 * p[0]) * p[2]);
    }
    std::vector<int> targets;
    for (const auto& c : mesh.classes())
      if (mesh.reference().col(c.front()).minCoeff() >= -1e-12) targets.push_back(c.front());
    const stokes::BoundaryOperators op(mesh);
    Matrix3Xd all, one;
    stokes::OperatorStats stats;
    op.single_layer(x, f, targets, all, &stats);
    EXPECT_EQ(stats.inner_far_late, 0);
    EXPECT_LT(stats.inner_far_elements, mesh.ne());
    std::printf("NE=%d NB=%d: inner tier on %ld of %d elements for %zu targets\n", ne, nb,
                stats.inner_far_elements, mesh.ne(), targets.size());
    long made = 0;
    for (size_t k = 0; k < targets.size(); ++k) {
      op.single_layer(x, f, std::vector<int>{targets[k]}, one, &stats);
      EXPECT_EQ(stats.inner_far_late, 0);
      made += stats.inner_far_elements;
      for (int c = 0; c < 3; ++c) ASSERT_EQ(one(c, 0), all(c, k)) << "target " << k;
    }
    std::printf("  one target per call: %.2f inner tiers per call\n",
                static_cast<double>(made) / static_cast<double>(targets.size()));
  }
}
