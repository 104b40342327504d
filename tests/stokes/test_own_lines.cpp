// stokes/own_lines: the own rules' lines interpolated across once per element and node row
// (OwnLines, OwnRules::element_line) give the sums of the per-rule path (load_chebyshev in the
// rule's symmetry, then line_sum) at every node of every element: the symmetries map each rule
// line to the element line it stands for, and the along sign reproduces the flipped coefficients.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "spectral/spectral.h"
#include "stokes/boundary_integral.h"
#include "stokes/line_sums.h"
#include "stokes/own_lines.h"
#include "stokes/own_rules.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

namespace {

// Largest difference between the two paths over all nodes of all elements, relative to the
// largest sum, on the ellipsoid (1.8, 0.7, 1.0) with a smooth density, options resolved for the
// mesh.
double path_difference(int ne, int nb, geometry::Division division,
                       stokes::QuadratureOptions options = {}) {
  const geometry::Mesh mesh(ne, nb, geometry::ElementMap::Equiangular, division);
  const Matrix3Xd x =
      geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.8, 0.7, 1.0));
  Matrix3Xd f(3, mesh.num_local());
  for (int m = 0; m < mesh.num_local(); ++m) {
    const Vector3d p = x.col(m);
    f.col(m) = Vector3d(std::sin(p[0] + 0.3), p[1] * p[2] - 0.4, std::exp(0.5 * p[0]) * p[2]);
  }
  const stokes::QuadratureOptions opt = stokes::resolve_defaults(mesh, options);
  const Eigen::VectorXd prod_w = spectral::product_weights(mesh.nodes());
  const stokes::OwnRules own(mesh, opt, prod_w);
  EXPECT_GT(own.ray_nodes(), 0);
  const Eigen::MatrixXd C = spectral::chebyshev_matrix(mesh.nodes());
  std::vector<stokes::ChebElement> ce(mesh.ne());
  for (int e = 0; e < mesh.ne(); ++e)
    stokes::chebyshev_element(nb, 0, 6, C, x, &f, e * nb * nb, ce[e]);
  stokes::OwnLines lines;
  lines.reset(mesh.ne(), nb, own.ray_nodes());
  for (int e = 0; e < mesh.ne(); ++e)
    for (int i = 0; i < nb; ++i) {
      lines.need(e, 0, i);
      lines.need(e, 1, i);
    }
  lines.allocate();
  for (int s = 0; s < lines.slots(); ++s) lines.make(s, own, ce);
  EXPECT_EQ(lines.lines(), 2L * mesh.ne() * nb * 2 * own.ray_nodes());

  stokes::Scratch sc;
  stokes::size_scratch(sc, nb, own.max_lines());
  const stokes::NodalBasis basis{mesh.nodes().data(), prod_w.data(), mesh.diff().data()};
  double diff = 0, scale = 0;
  for (int e = 0; e < mesh.ne(); ++e)
    for (int loc = 0; loc < nb * nb; ++loc) {
      const stokes::LineRule& r = own.rule(loc);
      const int sym = own.symmetry(loc);
      const Vector3d x0 = x.col(e * nb * nb + loc);
      double ref[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, acc[3] = {0, 0, 0};
      stokes::load_chebyshev(nb, 6, ce[e], sym, sc);
      stokes::line_sum<stokes::Mode::Single>(nb, 6, r, basis, stokes::OwnRules::sign(sym), x0,
                                             Vector3d::Zero(), sc, ref);
      std::vector<stokes::LineRows> rows(r.nl());
      for (int l = 0; l < r.nl(); ++l)
        rows[l] = lines.rows(e, stokes::OwnRules::element_line(r, l, sym), loc % nb, loc / nb);
      stokes::single_rows_sum(nb, r, rows.data(), x0, acc);
      for (int c = 0; c < 3; ++c) {
        diff = std::max(diff, std::abs(acc[c] - ref[c]));
        scale = std::max(scale, std::abs(ref[c]));
      }
    }
  std::printf("own lines NE=%d NB=%d: largest difference %.2e (relative)\n", ne, nb, diff / scale);
  return diff / scale;
}

}  // namespace

// Both paths do the same arithmetic up to the rounding of the 1-D bases at a flipped line
// coordinate (x_i + u (side - x_i) for the mirrored node instead of minus the rule's).
TEST(OwnLines, EveryNodeAndSymmetryAsThePerRulePath) {
  EXPECT_LT(path_difference(6, 10, geometry::Division::Cube), 1e-13);
  EXPECT_LT(path_difference(6, 9, geometry::Division::Cube), 1e-13);  // a centre node
  EXPECT_LT(path_difference(10, 8, geometry::Division::Box), 1e-13);
  EXPECT_LT(path_difference(14, 7, geometry::Division::Cube), 1e-13);  // elongated elements
  stokes::QuadratureOptions plain;                                     // plain Gauss along the rays
  plain.n_radial_inner = 0;
  EXPECT_LT(path_difference(6, 10, geometry::Division::Cube, plain), 1e-13);
}
