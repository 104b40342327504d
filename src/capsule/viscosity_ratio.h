// capflow/capsule/viscosity_ratio: the node velocities of a capsule whose inner fluid is lambda
// times as viscous as the outer one. Paper eq. 5 (method.md section 2),
//   (1 + lambda) u - 2 u_inf = -(1/(4 pi Ca)) INT S.f dS + ((1 - lambda)/(4 pi)) PV INT u.T.n dS,
// with PV INT u.T.n dS = DL[u] - 4 pi u(x0) (stokes/boundary_integral.h) becomes the
// second-kind equation
//   u - kappa DL[u] = u1,   kappa = (1 - lambda) / (8 pi),
// u1 the velocity at lambda = 1 (u_inf - SL[f] / (8 pi Ca)). Solved at the symmetry targets by
// GMRES (capsule/gmres.h), warm-started from the previous solution. The double layer is taken
// over the whole surface (the targets' values mirrored to every node) and assembled once per
// solve as a 3 targets x 3 targets matrix (stokes::BoundaryOperators::double_layer_matrix, the
// mirror images folded into its columns): the assembly costs about two applications of the
// operator, each GMRES iteration then a matrix-vector product (before: one application per
// iteration, 5-10 per solve; docs/performance.md).
// Spectrum: rigid-body motions have DL = 0 (eigenvalue 1 for every lambda); on the unit sphere
// the radial field x has DL[x] = 8 pi x, so u1 = x gives u = x / lambda: the system is singular
// as lambda -> 0 (the inner fluid cannot resist a change of volume).
#pragma once

#include <Eigen/Dense>
#include <memory>

#include "capsule/gmres.h"
#include "capsule/symmetry.h"
#include "stokes/boundary_integral.h"

namespace capflow::capsule {

// The viscosity ratios capflow solves for: (0, kMaxViscosityRatio].
constexpr double kMaxViscosityRatio = 100;

class ViscosityRatioSolver {
 public:
  // lambda in (0, kMaxViscosityRatio], options.tolerance in (0, 1) (std::invalid_argument naming
  // the range otherwise); ops and sym must outlive the solver.
  ViscosityRatioSolver(const stokes::BoundaryOperators& ops, const SymmetryMap& sym, double lambda,
                       GmresOptions options = {});
  ~ViscosityRatioSolver();

  // u at sym.targets() (3 x targets) on the surface x (3 x num_local) for the lambda = 1
  // velocity u1 at the targets. The first solve starts from u1, the next ones from the
  // previous solution. Throws std::runtime_error if GMRES does not reach the tolerance.
  // `assembled`: the double-layer matrix at x when it was assembled elsewhere (the rows of
  // matrix_rows from every rank of an MPI run); null: assembled here.
  Eigen::Matrix3Xd solve(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& u1,
                         GmresResult* result = nullptr, const stokes::RowMat* assembled = nullptr);

  // Rows 3 k .. 3 k + 2 of the double-layer matrix at x for k in `rows` (indices into
  // sym.targets()), in that order: each target's rows are the same whichever other rows are
  // assembled with them.
  stokes::RowMat matrix_rows(const Eigen::Matrix3Xd& x, const std::vector<int>& rows) const;

  // The warm start of the next solve (empty: start from u1), e.g. kept in a checkpoint so that a
  // resumed run continues bit for bit; set_warm_start checks its size (0 or 3 x targets).
  const Eigen::VectorXd& warm_start() const { return last_; }
  void set_warm_start(const Eigen::VectorXd& v);

  double lambda() const { return lambda_; }
  double kappa() const;  // (1 - lambda) / (8 pi)

 private:
  const stokes::BoundaryOperators& ops_;
  const SymmetryMap& sym_;
  double lambda_;
  GmresOptions options_;
  stokes::NodeExpansion expansion_;  // sym.expansion()
  std::unique_ptr<Gmres> gmres_;
  Eigen::VectorXd last_;  // the previous solution (the warm start)
};

}  // namespace capflow::capsule
