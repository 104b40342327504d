// The kernel sums give the same bits at every vector width (spectral/simd_width.h): the AVX-512
// clones work on 8 points per vector, the AVX2 ones on 4 and the SSE baseline on 2, with a block
// of 8 points split into parts that keep their own sums. Each operator at each width the CPU can
// run is compared bit for bit with the CPU's own width, on a deformed surface with a rough density
// and on a few targets near and on the surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "spectral/simd_width.h"
#include "stokes/boundary_integral.h"
#include "stokes_test_util.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;

namespace {

// Restores the CPU's width when a test ends, also on failure.
struct WidthGuard {
  ~WidthGuard() { spectral::limit_simd_width(8); }
};

// The largest |a - b| (0 for the same bits) and whether every entry has the same bits.
bool same_bits(const MatrixXd& a, const MatrixXd& b, double& diff) {
  diff = (a - b).cwiseAbs().maxCoeff();
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

// Runs f at the CPU's width and at every narrower one, and expects the same bits.
void expect_same_at_every_width(const char* what, const std::function<MatrixXd()>& f) {
  WidthGuard guard;
  spectral::limit_simd_width(8);
  const int cpu = spectral::simd_width();
  const MatrixXd ref = f();
  ASSERT_GT(ref.cwiseAbs().maxCoeff(), 0.0) << what;
  for (int w : {4, 2}) {
    if (w >= cpu) continue;
    spectral::limit_simd_width(w);
    ASSERT_EQ(spectral::simd_width(), w);
    double diff = 0.0;
    const bool same = same_bits(f(), ref, diff);
    std::printf("%s: width %d against %d: max |difference| %.3g\n", what, w, cpu, diff);
    EXPECT_TRUE(same) << what << " at width " << w << ": max |difference| " << diff;
  }
}

}  // namespace

TEST(SimdWidth, IsOneTheKernelsHaveAndCanBeLimited) {
  WidthGuard guard;
  spectral::limit_simd_width(8);
  const int cpu = spectral::simd_width();
  EXPECT_TRUE(cpu == 8 || cpu == 4 || cpu == 2) << cpu;
  spectral::limit_simd_width(2);
  EXPECT_EQ(spectral::simd_width(), 2);
  EXPECT_STREQ(spectral::simd_width_name(), "SSE2, 2 doubles");
  spectral::limit_simd_width(4);
  EXPECT_EQ(spectral::simd_width(), std::min(cpu, 4));
  spectral::limit_simd_width(8);
  EXPECT_EQ(spectral::simd_width(), cpu);
  EXPECT_THROW(spectral::limit_simd_width(3), std::invalid_argument);
  EXPECT_THROW(spectral::limit_simd_width(16), std::invalid_argument);
}

TEST(SimdWidth, EveryOperatorGivesTheSameBitsAtEveryWidth) {
  {
    WidthGuard guard;
    spectral::limit_simd_width(8);
    if (spectral::simd_width() <= 2)
      GTEST_SKIP() << "this CPU runs only the 2-wide kernels (" << spectral::simd_width_name()
                   << "): there is no narrower width to compare with";
  }
  // NB = 7 and 9: lines whose point counts are not multiples of 8 (partial blocks and parts)
  for (const auto& [ne, nb] : {std::pair{6, 7}, std::pair{10, 9}}) {
    geometry::Mesh mesh(ne, nb);
    stokes::BoundaryOperators op(mesh);
    stokes::QuadratureOptions jf;
    jf.interpolate_jf = true;
    stokes::BoundaryOperators op_jf(mesh, jf);
    const Matrix3Xd x =
        geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.6, 0.7, 1.0));
    const Matrix3Xd f = stokes::testing::random_density(mesh.num_local(), 5);
    std::vector<int> targets;
    for (int m = 0; m < mesh.num_local(); m += 7) targets.push_back(m);
    // points near the surface (near rules) and on it
    Matrix3Xd points(3, 3);
    points.col(0) = 1.02 * x.col(targets[1]);
    points.col(1) = 0.97 * x.col(targets[2]);
    points.col(2) = x.col(targets[3]);
    const std::string name = "NE=" + std::to_string(ne) + " NB=" + std::to_string(nb) + " ";
    expect_same_at_every_width((name + "single layer").c_str(), [&] {
      Matrix3Xd out;
      op.single_layer(x, f, targets, out);
      return MatrixXd(out);
    });
    expect_same_at_every_width((name + "single layer off the nodes").c_str(),
                               [&] { return MatrixXd(op.single_layer_at(x, f, points)); });
    expect_same_at_every_width((name + "single layer, J f interpolated").c_str(), [&] {
      Matrix3Xd out;
      op_jf.single_layer(x, f, targets, out);
      return MatrixXd(out);
    });
    expect_same_at_every_width((name + "double layer").c_str(), [&] {
      Matrix3Xd out;
      op.double_layer(x, f, targets, out);
      return MatrixXd(out);
    });
    expect_same_at_every_width((name + "double layer matrix").c_str(),
                               [&] { return MatrixXd(op.double_layer_matrix(x, targets)); });
    expect_same_at_every_width((name + "INT S.n").c_str(),
                               [&] { return MatrixXd(op.single_layer_normal(x, targets)); });
    expect_same_at_every_width((name + "INT T.n").c_str(),
                               [&] { return op.double_layer_normal(x, targets); });
  }
}
