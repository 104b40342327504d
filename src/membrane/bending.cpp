#include "membrane/bending.h"

#include <stdexcept>

#include "geometry/smoothing.h"
#include "geometry/surface.h"
#include "spectral/spectral.h"

namespace capflow::membrane {

using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::VectorXd;

VectorXd average_over_classes(const geometry::Mesh& mesh, const VectorXd& v) {
  VectorXd out = v;
  for (const std::vector<int>& cls : mesh.classes()) {
    if (cls.size() < 2) continue;
    double s = 0;
    for (int m : cls) s += v[m];
    for (int m : cls) out[m] = s / static_cast<double>(cls.size());
  }
  return out;
}

namespace {

using geometry::SmoothingBasis;

// The surface gradient t^a d_a phi of a scalar nodal field (3 x num_local), from each element's
// interpolant of phi, with the tangents of `basis`.
Matrix3Xd surface_gradient(const geometry::Mesh& mesh, const SmoothingBasis& basis,
                           const VectorXd& phi) {
  const VectorXd p1 = geometry::d_xi(mesh, phi.transpose()).transpose();
  const VectorXd p2 = geometry::d_eta(mesh, phi.transpose()).transpose();
  Matrix3Xd grad(3, phi.size());
  for (Eigen::Index k = 0; k < phi.size(); ++k)
    grad.col(k) = p1[k] * basis.upper1.col(k) + p2[k] * basis.upper2.col(k);
  return grad;
}

// Lap_s phi = div_s grad_s phi, the gradient made continuous across element edges before its
// divergence is taken: G = grad_s phi is averaged over coincident nodes (and put back in each
// node's tangent plane), then div_s G = t^a . dG/dtheta_a from each element's interpolant of G.
VectorXd laplace_beltrami(const geometry::Mesh& mesh, const SmoothingBasis& basis,
                          const Matrix3Xd& normal, const VectorXd& phi) {
  Matrix3Xd grad = surface_gradient(mesh, basis, phi);
  for (const std::vector<int>& cls : mesh.classes()) {
    if (cls.size() < 2) continue;
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int k : cls) s += grad.col(k);
    s /= static_cast<double>(cls.size());
    for (int k : cls) grad.col(k) = s - s.dot(normal.col(k)) * normal.col(k);
  }
  const MatrixXd g1 = geometry::d_xi(mesh, grad), g2 = geometry::d_eta(mesh, grad);
  VectorXd div(phi.size());
  for (Eigen::Index k = 0; k < phi.size(); ++k)
    div[k] = basis.upper1.col(k).dot(g1.col(k)) + basis.upper2.col(k).dot(g2.col(k));
  return average_over_classes(mesh, div);
}

}  // namespace

BendingGeometry bending_geometry(const geometry::Mesh& mesh, const SmoothingBasis& ref_basis,
                                 const Matrix3Xd& x) {
  BendingGeometry g;
  Matrix3Xd t1, t2;
  geometry::hermite_derivatives(mesh, ref_basis, x, &t1, &t2);
  const int n = mesh.num_local();
  g.n.resize(3, n);
  g.jac.resize(n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d c = t1.col(k).cross(t2.col(k));
    g.jac[k] = c.norm();
    g.n.col(k) = c / g.jac[k];
  }
  g.basis = geometry::basis_from_tangents(t1, t2);
  // The second derivatives from the smoothed tangents' own interpolants (differentiating x, not
  // the normal, whose interpolant converges far more slowly on the red cell).
  const MatrixXd d1 = t1, d2 = t2;
  const Matrix3Xd x11 = geometry::d_xi(mesh, d1), x22 = geometry::d_eta(mesh, d2);
  const Matrix3Xd x12 = 0.5 * (geometry::d_eta(mesh, d1) + geometry::d_xi(mesh, d2));
  g.H.resize(n);
  g.K.resize(n);
  for (int k = 0; k < n; ++k) {
    const double g11 = t1.col(k).squaredNorm(), g22 = t2.col(k).squaredNorm();
    const double g12 = t1.col(k).dot(t2.col(k));
    const double b11 = g.n.col(k).dot(x11.col(k)), b22 = g.n.col(k).dot(x22.col(k));
    const double b12 = g.n.col(k).dot(x12.col(k));
    const double det = g11 * g22 - g12 * g12;
    g.H[k] = -0.5 * (g22 * b11 - 2 * g12 * b12 + g11 * b22) / det;
    g.K[k] = (b11 * b22 - b12 * b12) / det;
  }
  g.H = average_over_classes(mesh, g.H);
  g.K = average_over_classes(mesh, g.K);
  return g;
}

Bending::Bending(const geometry::Mesh& mesh, const Matrix3Xd& reference,
                 const BendingOptions& options)
    : mesh_(mesh), opt_(options), ref_basis_(geometry::tangent_basis(mesh, reference)) {
  if (!(options.modulus >= 0))
    throw std::invalid_argument("bending modulus must be >= 0");
  if (reference.cols() != mesh.num_local())
    throw std::invalid_argument("Bending: the reference does not fit the mesh");
  if (options.model == BendingModel::Reference) {
    c0_ = 2 * bending_geometry(mesh, ref_basis_, reference).H;
  } else {
    c0_ = VectorXd::Constant(mesh.num_local(), options.c0);
  }
}

Matrix3Xd Bending::load(const Matrix3Xd& x) const {
  const int n = mesh_.num_local();
  if (x.cols() != n) throw std::invalid_argument("Bending::load: x does not fit the mesh");
  const double kb = opt_.modulus;
  if (kb == 0) return Matrix3Xd::Zero(3, n);
  const BendingGeometry g = bending_geometry(mesh_, ref_basis_, x);
  const VectorXd m = 2 * g.H - c0_;  // 2H - c0
  const VectorXd lap = laplace_beltrami(mesh_, g.basis, g.n, m);
  Matrix3Xd f(3, n);
  const bool varying = opt_.model == BendingModel::Reference;
  Matrix3Xd grad_c0;
  if (varying) grad_c0 = surface_gradient(mesh_, g.basis, c0_);
  for (int k = 0; k < n; ++k) {
    const double normal =
        -lap[k] - m[k] * (2 * g.H[k] * g.H[k] - 2 * g.K[k] + c0_[k] * g.H[k]);
    f.col(k) = kb * normal * g.n.col(k);
    if (varying) f.col(k) += kb * m[k] * grad_c0.col(k);
  }
  geometry::average_coincident(mesh_, &f);  // one value per coincident class
  return f;
}

double Bending::energy(const Matrix3Xd& x) const {
  const BendingGeometry g = bending_geometry(mesh_, ref_basis_, x);
  const spectral::Rule gl = spectral::gauss_lobatto(mesh_.nb());
  const int nb = mesh_.nb();
  double w = 0;
  for (int e = 0; e < mesh_.ne(); ++e)
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        const int k = (e * nb + j) * nb + i;
        const double m = 2 * g.H[k] - c0_[k];
        w += gl.w[i] * gl.w[j] * g.jac[k] * m * m;
      }
  return 0.5 * opt_.modulus * w;
}

VectorXd Bending::energy_density(const Matrix3Xd& x) const {
  if (x.cols() != mesh_.num_local())
    throw std::invalid_argument("Bending::energy_density: x does not fit the mesh");
  const VectorXd m = 2 * bending_geometry(mesh_, ref_basis_, x).H - c0_;
  return 0.5 * opt_.modulus * m.cwiseAbs2();
}

}  // namespace capflow::membrane
