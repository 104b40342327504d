// Validation: convergence in NB of the single- and double-layer operators on the ellipsoid
// (1.8, 0.7, 1.0) for smooth densities, against NB=20. Targets: the element-corner nodes
// (the same physical points for every NB; the own-element polar rule at a corner spans 3 or
// 4 elements, the hardest node type). Prints the table copied into docs/validation.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "stokes/boundary_integral.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

namespace {

struct Result {
  Matrix3Xd sl, dl;
};

// Corner nodes, one per class, in a fixed order (sorted by position).
std::vector<int> corners(const geometry::Mesh& m) {
  std::map<std::tuple<long, long, long>, int> sorted;
  const int nb = m.nb();
  for (const auto& c : m.classes()) {
    const int q = c.front();
    const int i = q % nb, j = (q / nb) % nb;
    if ((i == 0 || i == nb - 1) && (j == 0 || j == nb - 1)) {
      const Vector3d p = m.reference().col(q);
      sorted[{std::lround(p[0] * 1e6), std::lround(p[1] * 1e6), std::lround(p[2] * 1e6)}] = q;
    }
  }
  std::vector<int> r;
  for (auto& kv : sorted) r.push_back(kv.second);
  return r;
}

Result run(int ne, int nb) {
  geometry::Mesh mesh(ne, nb);
  stokes::BoundaryOperators op(mesh);
  const Matrix3Xd x =
      geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.8, 0.7, 1.0));
  Matrix3Xd f(3, mesh.num_local()), u(3, mesh.num_local());
  for (int m = 0; m < mesh.num_local(); ++m) {
    const Vector3d p = x.col(m);
    f.col(m) = Vector3d(std::sin(p[0] + 0.3), p[1] * p[2], std::exp(0.5 * p[0]));
    u.col(m) = Vector3d(p[1] * p[2], std::sin(p[0]), p[0] * p[0] - p[2]);
  }
  const std::vector<int> t = corners(mesh);
  Result r;
  op.single_layer(x, f, t, r.sl);
  op.double_layer(x, u, t, r.dl);
  return r;
}

}  // namespace

TEST(StokesConvergence, EllipsoidCorners) {
  for (int ne : {6, 10}) {
    const Result ref = run(ne, 20);
    const double ssl = ref.sl.cwiseAbs().maxCoeff(), sdl = ref.dl.cwiseAbs().maxCoeff();
    std::printf("NE=%d, %d corner targets, max|SL| %.3f max|DL| %.3f (NB=20)\n", ne,
                static_cast<int>(ref.sl.cols()), ssl, sdl);
    std::printf("| NB | SL rel. error | DL rel. error |\n|---|---|---|\n");
    std::map<int, std::pair<double, double>> err;
    for (int nb = 6; nb <= 16; nb += 2) {
      const Result r = run(ne, nb);
      const double esl = (r.sl - ref.sl).cwiseAbs().maxCoeff() / ssl;
      const double edl = (r.dl - ref.dl).cwiseAbs().maxCoeff() / sdl;
      err[nb] = {esl, edl};
      std::printf("| %d | %.2e | %.2e |\n", nb, esl, edl);
    }
    // exponential convergence: three decades from NB=6 to NB=14, and small at NB=16
    EXPECT_LT(err[14].first, 1e-3 * err[6].first) << ne;
    EXPECT_LT(err[14].second, 1e-3 * err[6].second) << ne;
    EXPECT_LT(err[16].first, 1e-7) << ne;
    EXPECT_LT(err[16].second, 1e-6) << ne;
  }
}
