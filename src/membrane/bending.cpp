#include "membrane/bending.h"

#include <stdexcept>

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

// Surface gradient components in the contravariant basis: u^a = g^ab d_b phi.
void contravariant_gradient(const geometry::Mesh& mesh, const geometry::SurfaceGeometry& g,
                            const VectorXd& phi, VectorXd* u1, VectorXd* u2) {
  const VectorXd p1 = geometry::d_xi(mesh, phi.transpose()).transpose();
  const VectorXd p2 = geometry::d_eta(mesh, phi.transpose()).transpose();
  const VectorXd det = g.g11.cwiseProduct(g.g22) - g.g12.cwiseProduct(g.g12);
  *u1 = (g.g22.cwiseProduct(p1) - g.g12.cwiseProduct(p2)).cwiseQuotient(det);
  *u2 = (g.g11.cwiseProduct(p2) - g.g12.cwiseProduct(p1)).cwiseQuotient(det);
}

// Lap_s phi = div_s grad_s phi, each derivative made continuous across element edges: the
// surface gradient G = u^a t_a (a vector in space) is averaged over coincident nodes before its
// divergence div_s G = t^a . dG/dtheta_a (t^a = g^ab t_b) is taken.
VectorXd laplace_beltrami(const geometry::Mesh& mesh, const geometry::SurfaceGeometry& g,
                          const VectorXd& phi) {
  VectorXd u1, u2;
  contravariant_gradient(mesh, g, phi, &u1, &u2);
  const int n = mesh.num_local();
  Matrix3Xd G(3, n);
  for (int k = 0; k < n; ++k) G.col(k) = u1[k] * g.t1.col(k) + u2[k] * g.t2.col(k);
  for (const std::vector<int>& cls : mesh.classes()) {
    if (cls.size() < 2) continue;
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int k : cls) s += G.col(k);
    s /= static_cast<double>(cls.size());
    for (int k : cls) G.col(k) = s - s.dot(g.n.col(k)) * g.n.col(k);
  }
  const MatrixXd G1 = geometry::d_xi(mesh, G), G2 = geometry::d_eta(mesh, G);
  const VectorXd det = g.g11.cwiseProduct(g.g22) - g.g12.cwiseProduct(g.g12);
  VectorXd div(n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d T1 = (g.g22[k] * g.t1.col(k) - g.g12[k] * g.t2.col(k)) / det[k];
    const Eigen::Vector3d T2 = (g.g11[k] * g.t2.col(k) - g.g12[k] * g.t1.col(k)) / det[k];
    div[k] = T1.dot(G1.col(k)) + T2.dot(G2.col(k));
  }
  return div;
}

}  // namespace

Bending::Bending(const geometry::Mesh& mesh, const Matrix3Xd& reference,
                 const BendingOptions& options)
    : mesh_(mesh), opt_(options) {
  if (!(options.modulus >= 0))
    throw std::invalid_argument("bending modulus must be >= 0");
  if (reference.cols() != mesh.num_local())
    throw std::invalid_argument("Bending: the reference does not fit the mesh");
  if (options.model == BendingModel::Reference) {
    const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh, reference);
    c0_ = 2 * average_over_classes(mesh, g.mean_curvature);
  } else {
    c0_ = VectorXd::Constant(mesh.num_local(), options.c0);
  }
}

Matrix3Xd Bending::load(const Matrix3Xd& x) const {
  const int n = mesh_.num_local();
  if (x.cols() != n) throw std::invalid_argument("Bending::load: x does not fit the mesh");
  const double kb = opt_.modulus;
  if (kb == 0) return Matrix3Xd::Zero(3, n);
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh_, x);
  const VectorXd H = average_over_classes(mesh_, g.mean_curvature);
  const VectorXd K = average_over_classes(mesh_, g.gaussian_curvature);
  const VectorXd m = 2 * H - c0_;  // 2H - c0
  const VectorXd lap = average_over_classes(mesh_, laplace_beltrami(mesh_, g, m));
  Matrix3Xd f(3, n);
  const bool varying = opt_.model == BendingModel::Reference;
  VectorXd c1, c2;
  if (varying) contravariant_gradient(mesh_, g, c0_, &c1, &c2);
  for (int k = 0; k < n; ++k) {
    const double normal =
        -lap[k] - m[k] * (2 * H[k] * H[k] - 2 * K[k] + c0_[k] * H[k]);
    f.col(k) = kb * normal * g.n.col(k);
    if (varying) f.col(k) += kb * m[k] * (c1[k] * g.t1.col(k) + c2[k] * g.t2.col(k));
  }
  // Continuous across element edges: one value per coincident class.
  for (const std::vector<int>& cls : mesh_.classes()) {
    if (cls.size() < 2) continue;
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int k : cls) s += f.col(k);
    s /= static_cast<double>(cls.size());
    for (int k : cls) f.col(k) = s;
  }
  return f;
}

double Bending::energy(const Matrix3Xd& x) const {
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh_, x);
  const spectral::Rule gl = spectral::gauss_lobatto(mesh_.nb());
  const int nb = mesh_.nb();
  double w = 0;
  for (int e = 0; e < mesh_.ne(); ++e)
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        const int k = (e * nb + j) * nb + i;
        const double m = 2 * g.mean_curvature[k] - c0_[k];
        w += gl.w[i] * gl.w[j] * g.jac[k] * m * m;
      }
  return 0.5 * opt_.modulus * w;
}

}  // namespace capflow::membrane
