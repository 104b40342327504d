#include "geometry/surface.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <vector>

#include "spectral/spectral.h"

namespace capflow::geometry {

namespace {

// One row of an element's nodal values as an nb x nb matrix (i along xi, j along eta) inside
// a rows x num_local field.
using ElementRow = Eigen::Map<MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>>;
using ConstElementRow =
    Eigen::Map<const MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>>;

// out = D f along xi (dir 0: D F per row and element) or along eta (dir 1: F D^T).
MatrixXd derivative(const Mesh& mesh, const MatrixXd& f, int dir) {
  if (f.cols() != mesh.num_local())
    throw std::invalid_argument("d_xi / d_eta: the field has " + std::to_string(f.cols()) +
                                " columns, the mesh " + std::to_string(mesh.num_local()) +
                                " nodes");
  const int nb = mesh.nb(), rows = static_cast<int>(f.rows());
  const MatrixXd& d = mesh.diff();
  MatrixXd out(rows, f.cols());
  const Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic> stride(rows * nb, rows);
  for (int e = 0; e < mesh.ne(); ++e)
    for (int r = 0; r < rows; ++r) {
      const long at = static_cast<long>(mesh.local(e, 0, 0)) * rows + r;
      const ConstElementRow in(f.data() + at, nb, nb, stride);
      ElementRow o(out.data() + at, nb, nb, stride);
      if (dir == 0)
        o.noalias() = d.lazyProduct(in);
      else
        o.noalias() = in.lazyProduct(d.transpose());
    }
  return out;
}

}  // namespace

MatrixXd d_xi(const Mesh& mesh, const MatrixXd& f) {
  return derivative(mesh, f, 0);
}

MatrixXd d_eta(const Mesh& mesh, const MatrixXd& f) {
  return derivative(mesh, f, 1);
}

SurfaceGeometry compute_geometry(const Mesh& mesh, const Matrix3Xd& x) {
  SurfaceGeometry g;
  const MatrixXd xd = x;
  g.x = x;
  g.t1 = d_xi(mesh, xd);
  g.t2 = d_eta(mesh, xd);
  g.x11 = d_xi(mesh, g.t1);
  g.x12 = d_eta(mesh, g.t1);
  g.x22 = d_eta(mesh, g.t2);
  const int n = mesh.num_local();
  g.n.resize(3, n);
  for (VectorXd* v : {&g.jac, &g.g11, &g.g12, &g.g22, &g.b11, &g.b12, &g.b22, &g.mean_curvature,
                      &g.gaussian_curvature})
    v->resize(n);
  for (int m = 0; m < n; ++m) {
    const Vector3d c = g.t1.col(m).cross(g.t2.col(m));
    g.jac[m] = c.norm();
    g.n.col(m) = c / g.jac[m];
    g.g11[m] = g.t1.col(m).squaredNorm();
    g.g12[m] = g.t1.col(m).dot(g.t2.col(m));
    g.g22[m] = g.t2.col(m).squaredNorm();
    g.b11[m] = g.n.col(m).dot(g.x11.col(m));
    g.b12[m] = g.n.col(m).dot(g.x12.col(m));
    g.b22[m] = g.n.col(m).dot(g.x22.col(m));
    const double det_g = g.g11[m] * g.g22[m] - g.g12[m] * g.g12[m];
    // g^ab b_ab = (g22 b11 - 2 g12 b12 + g11 b22) / det g
    const double trace =
        (g.g22[m] * g.b11[m] - 2.0 * g.g12[m] * g.b12[m] + g.g11[m] * g.b22[m]) / det_g;
    g.mean_curvature[m] = -0.5 * trace;
    g.gaussian_curvature[m] = (g.b11[m] * g.b22[m] - g.b12[m] * g.b12[m]) / det_g;
  }
  return g;
}

double max_normal_turning(const Mesh& mesh, const Matrix3Xd& n, int* node) {
  const int nb = mesh.nb();
  double worst = 0;
  int at = 0;
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i + 1 < nb; ++i)
        for (int dir = 0; dir < 2; ++dir) {
          const int a = dir == 0 ? mesh.local(e, i, j) : mesh.local(e, j, i);
          const int b = dir == 0 ? mesh.local(e, i + 1, j) : mesh.local(e, j, i + 1);
          // atan2 of |n_a x n_b| and n_a . n_b: accurate for small and large angles
          const double ang = std::atan2(n.col(a).cross(n.col(b)).norm(), n.col(a).dot(n.col(b)));
          if (ang > worst) worst = ang, at = a;
        }
  if (node) *node = at;
  return worst;
}

SurfacePoint ElementEvaluator::eval(int e, double s, double t) const {
  const int nb = mesh_.nb();
  constexpr int kMax = 64;  // Mesh: nb <= 64; no allocation per call (Newton loops call this)
  double ls[kMax], dls[kMax], lt[kMax], dlt[kMax], d2s[kMax], d2t[kMax];
  spectral::lagrange_basis(mesh_.nodes(), mesh_.bary(), s, ls, dls);
  spectral::lagrange_basis(mesh_.nodes(), mesh_.bary(), t, lt, dlt);
  // Second derivative of the interpolant: p''(s) = sum_k l_k'(s) (D p)_k, exact for degree nb-1.
  const MatrixXd& d = mesh_.diff();
  for (int i = 0; i < nb; ++i) {
    const double* di = d.col(i).data();
    double a = 0, b = 0;
    for (int k = 0; k < nb; ++k) {
      a += dls[k] * di[k];
      b += dlt[k] * di[k];
    }
    d2s[i] = a;
    d2t[i] = b;
  }
  // The element's nodes as 3 nb x nb: entry (3 i + c, j) is component c at node (i, j)
  // (Mesh::local), contracted with the t-bases first (w0, w1, w2: with l, l', l'' in t; rows
  // contiguous, so the 3 nb-long loop vectorises), then with the s-bases.
  const double* X = x_.data() + 3 * static_cast<long>(mesh_.local(e, 0, 0));
  const int rows = 3 * nb;
  double w0[3 * kMax], w1[3 * kMax], w2[3 * kMax];
  for (int r = 0; r < rows; ++r) {
    w0[r] = lt[0] * X[r];
    w1[r] = dlt[0] * X[r];
    w2[r] = d2t[0] * X[r];
  }
  for (int j = 1; j < nb; ++j) {
    const double* col = X + static_cast<long>(rows) * j;
    const double a = lt[j], b = dlt[j], c = d2t[j];
    for (int r = 0; r < rows; ++r) {
      w0[r] += a * col[r];
      w1[r] += b * col[r];
      w2[r] += c * col[r];
    }
  }
  SurfacePoint p;
  p.x.setZero();
  p.xs.setZero();
  p.xt.setZero();
  p.xss.setZero();
  p.xst.setZero();
  p.xtt.setZero();
  for (int i = 0; i < nb; ++i) {
    const Eigen::Map<const Vector3d> v0(w0 + 3 * i), v1(w1 + 3 * i), v2(w2 + 3 * i);
    p.x += ls[i] * v0;
    p.xs += dls[i] * v0;
    p.xss += d2s[i] * v0;
    p.xt += ls[i] * v1;
    p.xst += dls[i] * v1;
    p.xtt += ls[i] * v2;
  }
  return p;
}

MatrixXd to_gauss(const Mesh& mesh, const MatrixXd& f, const MatrixXd& interp) {
  const int nb = mesh.nb();
  const int nq = static_cast<int>(interp.rows());
  const int rows = static_cast<int>(f.rows());
  MatrixXd out(rows, mesh.ne() * nq * nq);
  MatrixXd tmp(rows, nq * nb);  // interpolated along xi: (a, j)
  for (int e = 0; e < mesh.ne(); ++e) {
    tmp.setZero();
    for (int j = 0; j < nb; ++j)
      for (int a = 0; a < nq; ++a)
        for (int i = 0; i < nb; ++i)
          tmp.col(j * nq + a) += interp(a, i) * f.col(mesh.local(e, i, j));
    for (int b = 0; b < nq; ++b)
      for (int a = 0; a < nq; ++a) {
        auto o = out.col((e * nq + b) * nq + a);
        o.setZero();
        for (int j = 0; j < nb; ++j) o += interp(b, j) * tmp.col(j * nq + a);
      }
  }
  return out;
}

Matrix3Xd resample_surface(const Mesh& from, const Matrix3Xd& x, const Mesh& to) {
  if (x.cols() != from.num_local())
    throw std::invalid_argument("resample_surface: x has " + std::to_string(x.cols()) +
                                " nodes, the source mesh " + std::to_string(from.num_local()));
  const ElementEvaluator ev(from, x);
  Matrix3Xd out(3, to.num_local());
  // One evaluation per distinct node, copied to its coincident locals.
  for (const std::vector<int>& cls : to.classes()) {
    const Mesh::Location at = from.locate(to.reference().col(cls.front()));
    const Vector3d p = ev.eval(at.e, at.xi, at.eta).x;
    for (int m : cls) out.col(m) = p;
  }
  return out;
}

QuadratureSurface sample_gauss(const Mesh& mesh, const Matrix3Xd& x, int nq) {
  QuadratureSurface q;
  q.nq = nq;
  const spectral::Rule r = spectral::gauss_legendre(nq);
  q.interp = spectral::interpolation_matrix(mesh.nodes(), r.x);
  const MatrixXd xd = x;
  q.x = to_gauss(mesh, xd, q.interp);
  q.t1 = to_gauss(mesh, d_xi(mesh, xd), q.interp);
  q.t2 = to_gauss(mesh, d_eta(mesh, xd), q.interp);
  const int n = static_cast<int>(q.x.cols());
  q.n.resize(3, n);
  q.w.resize(n);
  for (int e = 0; e < mesh.ne(); ++e)
    for (int b = 0; b < nq; ++b)
      for (int a = 0; a < nq; ++a) {
        const int k = (e * nq + b) * nq + a;
        const Vector3d c = q.t1.col(k).cross(q.t2.col(k));
        const double jac = c.norm();
        q.n.col(k) = c / jac;
        q.w[k] = r.w[a] * r.w[b] * jac;
      }
  return q;
}

}  // namespace capflow::geometry
