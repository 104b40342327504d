#include "capsule/viscosity_ratio.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace capflow::capsule {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

ViscosityRatioSolver::ViscosityRatioSolver(const stokes::BoundaryOperators& ops,
                                           const SymmetryMap& sym, double lambda,
                                           GmresOptions options)
    : ops_(ops), sym_(sym), lambda_(lambda), options_(options), expansion_(sym.expansion()) {
  if (!(lambda > 0 && lambda <= kMaxViscosityRatio))
    throw std::invalid_argument("viscosity_ratio = " + std::to_string(lambda) +
                                " is out of range: it must be in (0, " +
                                std::to_string(static_cast<int>(kMaxViscosityRatio)) + "]");
  if (!(options.tolerance > 0 && options.tolerance < 1))
    throw std::invalid_argument("krylov_tolerance = " + std::to_string(options.tolerance) +
                                " is out of range: it must be in (0, 1)");
}

ViscosityRatioSolver::~ViscosityRatioSolver() = default;

void ViscosityRatioSolver::set_warm_start(const Eigen::VectorXd& v) {
  if (v.size() != 0 && v.size() != 3 * static_cast<Eigen::Index>(sym_.targets().size()))
    throw std::invalid_argument("ViscosityRatioSolver: a warm start of " +
                                std::to_string(v.size()) + " values for " +
                                std::to_string(sym_.targets().size()) + " targets");
  if (!v.allFinite()) throw std::invalid_argument("ViscosityRatioSolver: a warm start not finite");
  last_ = v;
}

double ViscosityRatioSolver::kappa() const {
  return (1.0 - lambda_) / (8.0 * kPi);
}

stokes::RowMat ViscosityRatioSolver::matrix_rows(const Eigen::Matrix3Xd& x,
                                                 const std::vector<int>& rows) const {
  std::vector<int> targets;
  targets.reserve(rows.size());
  for (int k : rows) targets.push_back(sym_.targets().at(static_cast<size_t>(k)));
  return ops_.double_layer_matrix(x, targets, &expansion_);
}

Eigen::Matrix3Xd ViscosityRatioSolver::solve(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& u1,
                                             GmresResult* result, const stokes::RowMat* assembled) {
  const std::vector<int>& targets = sym_.targets();
  const int nt = static_cast<int>(targets.size());
  if (u1.cols() != nt)
    throw std::invalid_argument("ViscosityRatioSolver: u1 is not at the targets");
  if (result) *result = GmresResult{0, 0, true};
  if (lambda_ == 1.0) return u1;
  const int n = 3 * nt;
  if (!gmres_ || gmres_->size() != n) gmres_ = std::make_unique<Gmres>(n, options_);
  const double k = kappa();
  if (assembled && (assembled->rows() != n || assembled->cols() != n))
    throw std::invalid_argument("ViscosityRatioSolver: an assembled matrix of the wrong size");
  stokes::RowMat own;
  if (!assembled) own = ops_.double_layer_matrix(x, targets, &expansion_);
  const stokes::RowMat& dl = assembled ? *assembled : own;
  const Gmres::Operator A = [&](const Eigen::VectorXd& v, Eigen::VectorXd& out) {
    out.noalias() = dl * v;
    out = v - k * out;
  };
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(u1.data(), n);
  Eigen::VectorXd y = last_.size() == n ? last_ : b;
  const GmresResult r = gmres_->solve(A, b, &y);
  if (result) *result = r;
  if (!r.converged)
    throw std::runtime_error("viscosity ratio " + std::to_string(lambda_) +
                             ": GMRES stopped at relative residual " + std::to_string(r.residual) +
                             " after " + std::to_string(r.iterations) + " iterations (tolerance " +
                             std::to_string(options_.tolerance) + ")");
  last_ = y;
  return Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, nt);
}

}  // namespace capflow::capsule
