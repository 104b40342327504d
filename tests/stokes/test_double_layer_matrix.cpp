// The assembled double layer (BoundaryOperators::double_layer_matrix) is the same linear map as
// the density form (double_layer): on deformed surfaces, for densities that exercise every node,
// with and without an expansion of the columns, A vec(v) equals DL[expand(v)] to rounding.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "stokes/boundary_integral.h"
#include "stokes_test_util.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using stokes::testing::random_density;

namespace {

// Relative max difference of A vec(v) and DL[u] at the targets.
double mismatch(const stokes::RowMat& a, const Eigen::Ref<const VectorXd>& v, const Matrix3Xd& dl) {
  const VectorXd av = a * v;
  const Eigen::Map<const VectorXd> d(dl.data(), dl.size());
  return (av - d).cwiseAbs().maxCoeff() / d.cwiseAbs().maxCoeff();
}

}  // namespace

TEST(DoubleLayerMatrix, EqualsTheDensityFormOnDeformedSurfaces) {
  for (const auto& [ne, nb] : {std::pair{6, 8}, std::pair{10, 7}}) {
    geometry::Mesh mesh(ne, nb);
    stokes::BoundaryOperators op(mesh);
    const Matrix3Xd x =
        geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.5, 0.7, 1.1));
    // a smooth density (the coincident nodes of a class share it) and a rough one (every local
    // node its own value: the matrix must place each node's column, not only each class's)
    Matrix3Xd smooth(3, mesh.num_local());
    for (int m = 0; m < mesh.num_local(); ++m)
      smooth.col(m) = Vector3d(std::sin(x(0, m)), x(1, m) * x(2, m), std::exp(0.3 * x(0, m)));
    const Matrix3Xd rough = random_density(mesh.num_local(), 7);
    std::vector<int> targets;
    for (int m = 0; m < mesh.num_local(); m += 3) targets.push_back(m);
    stokes::OperatorStats s_matrix, s_density;
    const stokes::RowMat a = op.double_layer_matrix(x, targets, nullptr, &s_matrix);
    ASSERT_EQ(a.rows(), 3 * static_cast<int>(targets.size()));
    ASSERT_EQ(a.cols(), 3 * mesh.num_local());
    for (const Matrix3Xd* u : {static_cast<const Matrix3Xd*>(&smooth), &rough}) {
      Matrix3Xd dl;
      op.double_layer(x, *u, targets, dl, &s_density);
      const double e = mismatch(a, Eigen::Map<const VectorXd>(u->data(), u->size()), dl);
      std::printf("NE=%d NB=%d %s density: |A u - DL[u]| / |DL[u]| = %.2e\n", ne, nb,
                  u == &smooth ? "smooth" : "random", e);
      EXPECT_LT(e, 1e-12);
    }
    // the same quadrature: the same points
    EXPECT_EQ(s_matrix.pairs(), s_density.pairs());
    EXPECT_EQ(s_matrix.near_elements, s_density.near_elements);
  }
}

TEST(DoubleLayerMatrix, FoldsItsColumnsThroughAnExpansion) {
  geometry::Mesh mesh(6, 7);
  stokes::BoundaryOperators op(mesh);
  const Matrix3Xd x =
      geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.2, 0.9, 0.8));
  // an arbitrary expansion: 40 columns, each node a column and signs at random
  std::mt19937 gen(3);
  stokes::NodeExpansion ex;
  ex.columns = 40;
  for (int m = 0; m < mesh.num_local(); ++m) {
    ex.column.push_back(static_cast<int>(gen() % ex.columns));
    ex.sign.emplace_back(gen() % 2 ? 1.0 : -1.0, gen() % 2 ? 1.0 : -1.0, gen() % 2 ? 1.0 : -1.0);
  }
  const Matrix3Xd v = random_density(ex.columns, 11);
  Matrix3Xd u(3, mesh.num_local());
  for (int m = 0; m < mesh.num_local(); ++m)
    u.col(m) = ex.sign[m].cwiseProduct(v.col(ex.column[m]));
  const std::vector<int> targets = {0, 1, 30, 48, 49, 100, 150, 200, 293};
  const stokes::RowMat a = op.double_layer_matrix(x, targets, &ex);
  ASSERT_EQ(a.cols(), 3 * ex.columns);
  Matrix3Xd dl;
  op.double_layer(x, u, targets, dl);
  EXPECT_LT(mismatch(a, Eigen::Map<const VectorXd>(v.data(), v.size()), dl), 1e-12);
  // rigid translations are in the kernel of DL: every row sums to zero over the columns of a
  // constant field (all signs +1)
  ex.sign.assign(mesh.num_local(), Vector3d::Ones());
  const stokes::RowMat b = op.double_layer_matrix(x, targets, &ex);
  for (int j = 0; j < 3; ++j) {
    VectorXd c = VectorXd::Zero(3 * ex.columns);
    for (int col = 0; col < ex.columns; ++col) c[3 * col + j] = 1.0;
    EXPECT_LT((b * c).cwiseAbs().maxCoeff(), 1e-12 * b.cwiseAbs().maxCoeff()) << j;
  }
}

TEST(DoubleLayerMatrix, RejectsAnExpansionThatDoesNotFit) {
  geometry::Mesh mesh(6, 5);
  stokes::BoundaryOperators op(mesh);
  stokes::NodeExpansion ex;
  ex.columns = 3;
  ex.column.assign(mesh.num_local() - 1, 0);
  ex.sign.assign(mesh.num_local() - 1, Vector3d::Ones());
  EXPECT_THROW(op.double_layer_matrix(mesh.reference(), {0}, &ex), std::invalid_argument);
  ex.column.assign(mesh.num_local(), 3);
  ex.sign.assign(mesh.num_local(), Vector3d::Ones());
  EXPECT_THROW(op.double_layer_matrix(mesh.reference(), {0}, &ex), std::invalid_argument);
}
