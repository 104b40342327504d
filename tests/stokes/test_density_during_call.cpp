// BoundaryOperators::single_layer with the density made during the call (a DensityFn, run by the
// team's first thread while the others make the data that need only x): the same bits as the
// call with the density given, on one and two threads and with interpolate_jf; the density
// function runs once per call; its exception reaches the caller and leaves the operator usable;
// a density of the wrong size is refused.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "stokes/boundary_integral.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

namespace {

struct Case {
  geometry::Mesh mesh{6, 10};
  Matrix3Xd x, f;
  std::vector<int> targets;
  Case() {
    x = geometry::map_points(mesh.reference(), geometry::lamellar_map(2.0, 0.6, 1.0, 0.3));
    f.resize(3, mesh.num_local());
    for (int m = 0; m < mesh.num_local(); ++m) {
      const Vector3d p = x.col(m);
      f.col(m) = Vector3d(std::sin(p[0] + 0.3), p[1] * p[2] - 0.4, std::exp(0.5 * p[0]) * p[2]);
    }
    for (const auto& c : mesh.classes())
      if (mesh.reference().col(c.front()).minCoeff() >= -1e-12) targets.push_back(c.front());
  }
};

}  // namespace

TEST(StokesDensityDuringCall, SameBitsAsTheGivenDensity) {
  const Case c;
  const int threads = omp_get_max_threads();
  for (bool jf : {false, true}) {
    stokes::QuadratureOptions q;
    q.interpolate_jf = jf;
    const stokes::BoundaryOperators op(c.mesh, q);
    for (int team : {1, 2}) {
      omp_set_num_threads(team);
      Matrix3Xd given, made;
      op.single_layer(c.x, c.f, c.targets, given);
      int calls = 0;
      op.single_layer(
          c.x,
          [&](Matrix3Xd& f) {
            ++calls;
            f = c.f;
          },
          c.targets, made);
      EXPECT_EQ(calls, 1);
      ASSERT_EQ(made.cols(), given.cols());
      EXPECT_EQ((made - given).cwiseAbs().maxCoeff(), 0.0) << "jf " << jf << " team " << team;
      EXPECT_GT(given.cwiseAbs().maxCoeff(), 0.1);
    }
  }
  omp_set_num_threads(threads);
}

TEST(StokesDensityDuringCall, AnExceptionReachesTheCallerAndTheOperatorStaysUsable) {
  const Case c;
  const stokes::BoundaryOperators op(c.mesh);
  const int threads = omp_get_max_threads();
  for (int team : {1, 2}) {
    omp_set_num_threads(team);
    Matrix3Xd out;
    EXPECT_THROW(
        op.single_layer(
            c.x, [](Matrix3Xd&) { throw std::runtime_error("membrane failed"); }, c.targets, out),
        std::runtime_error);
    Matrix3Xd given, made;
    op.single_layer(c.x, c.f, c.targets, given);
    op.single_layer(
        c.x, [&](Matrix3Xd& f) { f = c.f; }, c.targets, made);
    EXPECT_EQ((made - given).cwiseAbs().maxCoeff(), 0.0);
  }
  omp_set_num_threads(threads);
}

TEST(StokesDensityDuringCall, ADensityOfTheWrongSizeIsRefused) {
  const Case c;
  const stokes::BoundaryOperators op(c.mesh);
  Matrix3Xd out;
  EXPECT_THROW(op.single_layer(
                   c.x, [](Matrix3Xd& f) { f = Matrix3Xd::Zero(3, 5); }, c.targets, out),
               std::invalid_argument);
}
