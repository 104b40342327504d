// capsule/gmres and capsule/viscosity_ratio: GMRES against a dense solve; the second-kind
// equation u - kappa DL[u] = u1 of viscosity ratio lambda against its closed-form eigenvectors
// on the unit sphere: rigid-body motions (DL = 0: u = u1 for every lambda) and the radial field
// (DL[x] = 8 pi x: u = x / lambda).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "capsule/gmres.h"
#include "capsule/symmetry.h"
#include "capsule/viscosity_ratio.h"
#include "geometry/mesh.h"
#include "stokes/boundary_integral.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

TEST(Gmres, SolvesANonsymmetricSystemAndStartsFromTheGuess) {
  const int n = 40;
  MatrixXd A = MatrixXd::Random(n, n) * 0.3;
  A.diagonal().array() += 4.0;
  const VectorXd exact = VectorXd::LinSpaced(n, -1.0, 2.0);
  const VectorXd b = A * exact;
  const capsule::Gmres::Operator op = [&](const VectorXd& v, VectorXd& out) { out = A * v; };
  capsule::Gmres g(n, {20, 10, 1e-12});
  VectorXd y = VectorXd::Zero(n);
  const capsule::GmresResult r = g.solve(op, b, &y);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.iterations, 5);
  EXPECT_LT((y - exact).norm() / exact.norm(), 1e-10);
  EXPECT_LT((A * y - b).norm() / b.norm(), 1e-11);
  // from the solution itself: nothing left to do
  VectorXd z = exact;
  EXPECT_EQ(g.solve(op, b, &z).iterations, 0);
  EXPECT_LT((z - exact).norm() / exact.norm(), 1e-12);
}

TEST(Gmres, AnOperatorErrorReachesTheCaller) {
  capsule::Gmres g(5);
  VectorXd y = VectorXd::Zero(5);
  const capsule::Gmres::Operator bad = [](const VectorXd&, VectorXd&) {
    throw std::runtime_error("operator failed");
  };
  EXPECT_THROW(g.solve(bad, VectorXd::Ones(5), &y), std::runtime_error);
  // the solver is still usable
  const capsule::Gmres::Operator id = [](const VectorXd& v, VectorXd& out) { out = 2.0 * v; };
  EXPECT_TRUE(g.solve(id, VectorXd::Ones(5), &y).converged);
  EXPECT_LT((y - VectorXd::Constant(5, 0.5)).norm(), 1e-12);
}

namespace {
// The unit sphere's nodes at the targets of `sym`.
Matrix3Xd at_targets(const Matrix3Xd& x, const capsule::SymmetryMap& sym) {
  Matrix3Xd t(3, sym.targets().size());
  for (size_t k = 0; k < sym.targets().size(); ++k) t.col(k) = x.col(sym.targets()[k]);
  return t;
}
}  // namespace

TEST(ViscosityRatio, RigidBodyMotionsAreLeftAsTheyAre) {
  geometry::Mesh mesh(6, 8);
  const stokes::BoundaryOperators ops(mesh);
  const capsule::SymmetryMap all(mesh, capsule::SymmetryKind::None);
  const Matrix3Xd& x = mesh.reference();
  const Matrix3Xd xt = at_targets(x, all);
  const Vector3d U(0.3, -0.2, 0.5), w(0.1, 0.4, -0.3);
  Matrix3Xd u1(3, xt.cols());
  for (int k = 0; k < xt.cols(); ++k) u1.col(k) = U + w.cross(xt.col(k));
  for (double lambda : {0.2, 5.0, 100.0}) {
    capsule::ViscosityRatioSolver s(ops, all, lambda);
    capsule::GmresResult r;
    const Matrix3Xd u = s.solve(x, u1, &r);
    EXPECT_LT((u - u1).cwiseAbs().maxCoeff(), 1e-7) << "lambda " << lambda;
    std::printf("rigid motion, lambda %g: %d iterations, residual %.1e\n", lambda, r.iterations,
                r.residual);
  }
}

// DL[x] = 8 pi x holds on the exact sphere; on the interpolated one the error falls spectrally
// with NB (the geometry's interpolation error).
TEST(ViscosityRatio, TheRadialFieldOnTheSphereIsDividedByLambda) {
  const std::vector<double> lambdas = {0.2, 0.5, 1.0, 5.0, 100.0};
  std::vector<double> previous(lambdas.size(), 0.0);
  for (int nb : {6, 8, 10, 12}) {
    geometry::Mesh mesh(6, nb);
    const stokes::BoundaryOperators ops(mesh);
    const capsule::SymmetryMap octant(mesh, capsule::SymmetryKind::Octant);
    const Matrix3Xd& x = mesh.reference();
    const Matrix3Xd u1 = at_targets(x, octant);
    for (size_t i = 0; i < lambdas.size(); ++i) {
      const double lambda = lambdas[i];
      capsule::ViscosityRatioSolver s(ops, octant, lambda);
      capsule::GmresResult r;
      const Matrix3Xd u = s.solve(x, u1, &r);
      const double err = (u - u1 / lambda).cwiseAbs().maxCoeff() * lambda;
      EXPECT_TRUE(r.converged);
      if (lambda == 1.0) {
        EXPECT_EQ(err, 0.0);
      } else {
        if (nb > 6) {
          EXPECT_LT(err, previous[i] / 5) << "NB " << nb << ", lambda " << lambda;
        }
        if (nb == 12) {
          EXPECT_LT(err, 5e-8) << "lambda " << lambda;
        }
      }
      previous[i] = err;
      std::printf("NB %d, lambda %g: %d iterations, residual %.1e, error %.2e\n", nb, lambda,
                  r.iterations, r.residual, err);
      capsule::GmresResult again;
      s.solve(x, u1, &again);
      EXPECT_LE(again.iterations, 1) << "lambda " << lambda;
    }
  }
}

// A sphere without membrane stress (the capsule at rest, f = 0: u1 = u_inf) in the pure strain
// u_inf = E x moves with the surface velocity u = 5 / (2 lambda + 3) E x: the Stokes solution
// of a sphere with continuous velocity and traction across its surface (the instantaneous
// velocity of Taylor's (1932) drop without interfacial tension; lambda = 1: u = u_inf,
// lambda -> infinity: a rigid sphere in a strain, at rest). Normal and tangential parts alike.
TEST(ViscosityRatio, AnUnstressedSphereInAStrainMovesAtFiveOverTwoLambdaPlusThree) {
  geometry::Mesh mesh(6, 10);
  const stokes::BoundaryOperators ops(mesh);
  const capsule::SymmetryMap octant(mesh, capsule::SymmetryKind::Octant);
  const Matrix3Xd& x = mesh.reference();
  const Eigen::Matrix3d E = Vector3d(1, -1, 0).asDiagonal();  // planar extension
  const Matrix3Xd u1 = E * at_targets(x, octant);
  for (double lambda : {0.2, 0.5, 2.0, 5.0, 20.0}) {
    capsule::ViscosityRatioSolver s(ops, octant, lambda);
    const Matrix3Xd u = s.solve(x, u1);
    const double a = 5.0 / (2.0 * lambda + 3.0);
    double normal = 0, tangential = 0;
    for (int k = 0; k < u.cols(); ++k) {
      const Vector3d n = at_targets(x, octant).col(k).normalized();
      const Vector3d d = u.col(k) - a * u1.col(k);
      normal = std::max(normal, std::abs(d.dot(n)));
      tangential = std::max(tangential, (d - d.dot(n) * n).norm());
    }
    EXPECT_LT(normal, 1e-7) << "lambda " << lambda;
    EXPECT_LT(tangential, 2e-6) << "lambda " << lambda;
  }
}

TEST(ViscosityRatio, RefusesRatiosOutsideTheRange) {
  geometry::Mesh mesh(6, 4);
  const stokes::BoundaryOperators ops(mesh);
  const capsule::SymmetryMap octant(mesh, capsule::SymmetryKind::Octant);
  for (double bad : {0.0, -1.0, 100.5}) {
    EXPECT_THROW(capsule::ViscosityRatioSolver(ops, octant, bad), std::invalid_argument) << bad;
  }
}
