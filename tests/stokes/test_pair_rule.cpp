// stokes/pair_rule on its own: the choice of a (target, element) pair's rule from the element's
// bounds is the one the exact distance h gives (the nearest-point search is skipped only where
// the bounds decide), a point far away takes the far tier 0 without a search, and a point on an
// element takes the near rule with p* on it.
#include <gtest/gtest.h>

#include <random>

#include "geometry/element_search.h"
#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "stokes/element_bounds.h"
#include "stokes/pair_rule.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

namespace {

// The rule the exact distance h gives (no shortcut).
stokes::PairRule by_distance(double h, const stokes::PairThresholds& t) {
  stokes::PairRule r;
  r.near = h < t.near;
  r.tier = h < t.mid ? (h < t.inner ? 2 : 1) : 0;
  return r;
}

}  // namespace

TEST(PairRule, IsTheChoiceOfTheExactDistance) {
  const geometry::Mesh mesh(6, 8);
  const Matrix3Xd x =
      geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.6, 0.7, 1.0));
  std::vector<stokes::ElementBounds> b;
  for (int e = 0; e < mesh.ne(); ++e) b.push_back(stokes::element_bounds(x, mesh.nb(), e));
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> node(0, mesh.num_local() - 1);
  std::uniform_real_distribution<double> scale(0.7, 1.5), jitter(-0.1, 0.1);
  long searched = 0, skipped = 0, near = 0, tiers[3] = {0, 0, 0};
  for (int i = 0; i < 400; ++i) {
    // points at and about the surface: a node moved along its radius and sideways
    const Vector3d x0 = scale(rng) * x.col(node(rng)) + Vector3d(jitter(rng), jitter(rng), 0.0);
    for (int e = 0; e < mesh.ne(); ++e) {
      const double size = 2.0 * b[e].radius;
      for (const stokes::PairThresholds& t :
           {stokes::PairThresholds{0.1 * size, 0.4 * size, 1.2 * size},
            stokes::PairThresholds{0.2 * size, 0.0, 0.8 * size}}) {
        const stokes::PairRule r = stokes::choose_pair_rule(mesh, x, e, b[e], x0, t);
        int best = 0;
        geometry::nearest_node(mesh, x, e, x0, &best);
        const geometry::NearestPoint np = geometry::nearest_point(mesh, x, e, x0, best);
        const stokes::PairRule exact = by_distance(np.h, t);
        ASSERT_EQ(r.near, exact.near) << "point " << i << " element " << e << " h " << np.h;
        if (!r.near) ASSERT_EQ(r.tier, exact.tier) << "point " << i << " element " << e;
        if (r.near) {
          EXPECT_TRUE(r.searched);  // the near rule needs p*
          EXPECT_EQ(r.np.h, np.h);
          ++near;
        } else {
          ++tiers[r.tier];
        }
        (r.searched ? searched : skipped) += 1;
      }
    }
  }
  // every branch taken, with and without a search
  EXPECT_GT(near, 0);
  for (long n : tiers) EXPECT_GT(n, 0);
  EXPECT_GT(skipped, 0);
  EXPECT_GT(searched, near);  // searches that found the pair not near
}

TEST(PairRule, FarAwayIsTierZeroWithoutASearchAndOnTheElementIsNear) {
  const geometry::Mesh mesh(6, 8);
  const Matrix3Xd& x = mesh.reference();
  const stokes::ElementBounds b = stokes::element_bounds(x, mesh.nb(), 0);
  const stokes::PairThresholds t{0.1, 0.3, 0.9};
  const stokes::PairRule far = stokes::choose_pair_rule(mesh, x, 0, b, 10.0 * b.centre, t);
  EXPECT_FALSE(far.near);
  EXPECT_EQ(far.tier, 0);
  EXPECT_FALSE(far.searched);
  const int mid_node = (mesh.nb() / 2) * mesh.nb() + mesh.nb() / 2;
  const stokes::PairRule on = stokes::choose_pair_rule(mesh, x, 0, b, x.col(mid_node), t);
  EXPECT_TRUE(on.near);
  EXPECT_TRUE(on.searched);
  EXPECT_LT(on.np.h, 1e-12);
}
