#include "membrane/membrane.h"

#include <cmath>
#include <stdexcept>

#include "geometry/surface.h"
#include "spectral/spectral.h"

namespace capflow::membrane {

namespace {

// Inverse of the 2x2 metric (a11, a12; a12, a22); returns det.
double invert_metric(double a11, double a12, double a22, double* i11, double* i12, double* i22) {
  const double det = a11 * a22 - a12 * a12;
  *i11 = a22 / det;
  *i12 = -a12 / det;
  *i22 = a11 / det;
  return det;
}

void check_area(double jac) {
  if (!(std::isfinite(jac) && jac > 0.0))
    throw std::domain_error("membrane: degenerate or non-finite current surface element");
}

}  // namespace

PointKinematics point_kinematics(const Vector3d& T1, const Vector3d& T2, const Vector3d& t1,
                                 const Vector3d& t2) {
  double gi11, gi12, gi22;
  const double det_ref = invert_metric(T1.dot(T1), T1.dot(T2), T2.dot(T2), &gi11, &gi12, &gi22);
  const Vector3d R1 = gi11 * T1 + gi12 * T2, R2 = gi12 * T1 + gi22 * T2;  // T^a
  PointKinematics k;
  k.A = t1 * R1.transpose() + t2 * R2.transpose();
  k.B = gi11 * t1 * t1.transpose() + gi12 * (t1 * t2.transpose() + t2 * t1.transpose()) +
        gi22 * t2 * t2.transpose();
  const Vector3d c = t1.cross(t2);
  const double jac = c.norm();
  k.n = c / jac;
  k.P = Matrix3d::Identity() - k.n * k.n.transpose();
  k.js = jac / std::sqrt(det_ref);
  k.i1 = gi11 * t1.dot(t1) + 2.0 * gi12 * t1.dot(t2) + gi22 * t2.dot(t2) - 2.0;
  k.i2 = k.js * k.js - 1.0;
  return k;
}

Matrix3d tension_tensor(const Law& law, const PointKinematics& k) {
  double cb, cp;
  law.tension_coefficients(k.i1, k.js, &cb, &cp);
  return cb * k.B + cp * k.P;
}

PointPrincipal point_principal(const Law& law, const PointKinematics& k) {
  // B restricted to the tangent plane in an orthonormal basis (u1, u2); closed-form 2x2 eigen.
  Vector3d u1 = k.P.col(0);
  for (int c = 1; c < 3; ++c)
    if (k.P.col(c).squaredNorm() > u1.squaredNorm()) u1 = k.P.col(c);
  u1.normalize();
  const Vector3d u2 = k.n.cross(u1);
  const double b11 = u1.dot(k.B * u1), b12 = u1.dot(k.B * u2), b22 = u2.dot(k.B * u2);
  const double m = 0.5 * (b11 + b22), h = 0.5 * (b11 - b22);
  const double r = std::hypot(h, b12);
  PointPrincipal p;
  p.lambda1 = std::sqrt(m + r);
  p.lambda2 = k.js / p.lambda1;  // (l1 l2 = Js) avoids cancellation in m - r
  const double th = 0.5 * std::atan2(b12, h);
  p.stretch_dir1 = std::cos(th) * u1 + std::sin(th) * u2;
  p.stretch_dir2 = k.n.cross(p.stretch_dir1);
  double cb, cp;
  law.tension_coefficients(k.i1, k.js, &cb, &cp);
  const double ta = cp + cb * p.lambda1 * p.lambda1, tb = cp + cb * p.lambda2 * p.lambda2;
  if (ta >= tb) {
    p.tension1 = ta;
    p.tension2 = tb;
    p.tension_dir1 = p.stretch_dir1;
    p.tension_dir2 = p.stretch_dir2;
  } else {
    p.tension1 = tb;
    p.tension2 = ta;
    p.tension_dir1 = p.stretch_dir2;
    p.tension_dir2 = p.stretch_dir1;
  }
  return p;
}

namespace {
Matrix3Xd reference_derivative(const geometry::Mesh& mesh, const Matrix3Xd& reference, int dir) {
  if (reference.cols() != mesh.num_local())
    throw std::invalid_argument("Membrane: reference has wrong size");
  const MatrixXd xr = reference;
  return dir == 0 ? geometry::d_xi(mesh, xr) : geometry::d_eta(mesh, xr);
}
}  // namespace

Membrane::Membrane(const geometry::Mesh& mesh, const Matrix3Xd& reference,
                   std::shared_ptr<const Law> law, int nq)
    : Membrane(mesh, reference_derivative(mesh, reference, 0),
               reference_derivative(mesh, reference, 1), std::move(law), nq) {}

Membrane::Membrane(const geometry::Mesh& mesh, const Matrix3Xd& ref_t1, const Matrix3Xd& ref_t2,
                   std::shared_ptr<const Law> law, int nq)
    : mesh_(mesh), law_(std::move(law)), nq_(nq > 0 ? nq : mesh.nb() + 4) {
  if (!law_) throw std::invalid_argument("Membrane: null law");
  const int n = mesh.num_local();
  if (ref_t1.cols() != n || ref_t2.cols() != n)
    throw std::invalid_argument("Membrane: reference tangents have wrong size");
  ref_t1_ = ref_t1;
  ref_t2_ = ref_t2;
  for (VectorXd* v : {&gi11_, &gi12_, &gi22_, &sqrt_g_}) v->resize(n);
  for (int m = 0; m < n; ++m) {
    const Vector3d T1 = ref_t1_.col(m), T2 = ref_t2_.col(m);
    const double det =
        invert_metric(T1.dot(T1), T1.dot(T2), T2.dot(T2), &gi11_[m], &gi12_[m], &gi22_[m]);
    if (!(det > 0)) throw std::invalid_argument("Membrane: degenerate reference surface");
    sqrt_g_[m] = std::sqrt(det);
  }
  // Reference data at the Gauss points for the energy integral.
  const spectral::Rule rule = spectral::gauss_legendre(nq_);
  interp_ = spectral::interpolation_matrix(mesh.nodes(), rule.x);
  const MatrixXd q1 = geometry::to_gauss(mesh, MatrixXd(ref_t1_), interp_);
  const MatrixXd q2 = geometry::to_gauss(mesh, MatrixXd(ref_t2_), interp_);
  const int nqt = static_cast<int>(q1.cols());
  for (VectorXd* v : {&qgi11_, &qgi12_, &qgi22_, &qsqrt_g_, &qweight_}) v->resize(nqt);
  for (int e = 0; e < mesh.ne(); ++e)
    for (int b = 0; b < nq_; ++b)
      for (int a = 0; a < nq_; ++a) {
        const int k = (e * nq_ + b) * nq_ + a;
        const Vector3d T1 = q1.col(k), T2 = q2.col(k);
        const double det =
            invert_metric(T1.dot(T1), T1.dot(T2), T2.dot(T2), &qgi11_[k], &qgi12_[k], &qgi22_[k]);
        qsqrt_g_[k] = std::sqrt(det);
        qweight_[k] = rule.w[a] * rule.w[b];
      }
}

void Membrane::set_law(std::shared_ptr<const Law> law) {
  if (!law) throw std::invalid_argument("Membrane: null law");
  law_ = std::move(law);
}

void Membrane::current_tangents(const Matrix3Xd& x, Matrix3Xd* t1, Matrix3Xd* t2) const {
  const int nb = mesh_.nb(), ne = mesh_.ne(), n = mesh_.num_local();
  if (x.cols() != n) throw std::invalid_argument("Membrane: positions have wrong size");
  t1->resize(3, n);
  t2->resize(3, n);
  const MatrixXd& d = mesh_.diff();
  for (int e = 0; e < ne; ++e) {
    const int base = e * nb * nb;
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        Vector3d a = Vector3d::Zero(), b = Vector3d::Zero();
        for (int k = 0; k < nb; ++k) {
          a += d(i, k) * x.col(base + j * nb + k);
          b += d(j, k) * x.col(base + k * nb + i);
        }
        t1->col(base + j * nb + i) = a;
        t2->col(base + j * nb + i) = b;
      }
  }
}

void Membrane::traction(const Matrix3Xd& x, Matrix3Xd* f) const {
  Matrix3Xd t1, t2;
  current_tangents(x, &t1, &t2);
  traction_from_tangents(t1, t2, f);
}

void Membrane::traction_from_tangents(const Matrix3Xd& t1, const Matrix3Xd& t2, Matrix3Xd* f) const {
  const int nb = mesh_.nb(), ne = mesh_.ne(), n = mesh_.num_local();
  if (t1.cols() != n || t2.cols() != n) throw std::invalid_argument("Membrane: tangents have wrong size");
  // q^a = sqrt(g) (cb G^ab + cp g^ab) t_b.
  Matrix3Xd q1(3, n), q2(3, n);
  VectorXd jac(n);
  const Law& law = *law_;
  for (int m = 0; m < n; ++m) {
    const Vector3d a1 = t1.col(m), a2 = t2.col(m);
    const double g11 = a1.dot(a1), g12 = a1.dot(a2), g22 = a2.dot(a2);
    double c11, c12, c22;
    const double det = invert_metric(g11, g12, g22, &c11, &c12, &c22);
    const double sg = std::sqrt(det);
    check_area(sg);
    jac[m] = sg;
    const double js = sg / sqrt_g_[m];
    const double i1 = gi11_[m] * g11 + 2.0 * gi12_[m] * g12 + gi22_[m] * g22 - 2.0;
    double cb, cp;
    law.tension_coefficients(i1, js, &cb, &cp);
    const double s11 = sg * (cb * gi11_[m] + cp * c11);
    const double s12 = sg * (cb * gi12_[m] + cp * c12);
    const double s22 = sg * (cb * gi22_[m] + cp * c22);
    q1.col(m) = s11 * a1 + s12 * a2;
    q2.col(m) = s12 * a1 + s22 * a2;
  }
  f->resize(3, n);
  const MatrixXd& d = mesh_.diff();
  for (int e = 0; e < ne; ++e) {
    const int base = e * nb * nb;
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        Vector3d s = Vector3d::Zero();
        for (int k = 0; k < nb; ++k) {
          s += d(i, k) * q1.col(base + j * nb + k);
          s += d(j, k) * q2.col(base + k * nb + i);
        }
        const int m = base + j * nb + i;
        f->col(m) = -s / jac[m];
      }
  }
}

Matrix3Xd Membrane::traction(const Matrix3Xd& x) const {
  Matrix3Xd f;
  traction(x, &f);
  return f;
}

MembraneFields Membrane::fields(const Matrix3Xd& x) const {
  Matrix3Xd t1, t2;
  current_tangents(x, &t1, &t2);
  return fields_from_tangents(t1, t2);
}

MembraneFields Membrane::fields_from_tangents(const Matrix3Xd& t1, const Matrix3Xd& t2) const {
  const int n = mesh_.num_local();
  if (t1.cols() != n || t2.cols() != n) throw std::invalid_argument("Membrane: tangents have wrong size");
  MembraneFields out;
  out.A.resize(n);
  out.B.resize(n);
  out.tau.resize(n);
  for (VectorXd* v : {&out.js, &out.i1, &out.i2, &out.lambda1, &out.lambda2, &out.tension1,
                      &out.tension2, &out.energy_density})
    v->resize(n);
  for (Matrix3Xd* v : {&out.stretch_dir1, &out.stretch_dir2, &out.tension_dir1, &out.tension_dir2})
    v->resize(3, n);
  for (int m = 0; m < n; ++m) {
    check_area(t1.col(m).cross(t2.col(m)).norm());
    const PointKinematics k =
        point_kinematics(ref_t1_.col(m), ref_t2_.col(m), t1.col(m), t2.col(m));
    const PointPrincipal p = point_principal(*law_, k);
    out.A[m] = k.A;
    out.B[m] = k.B;
    out.tau[m] = tension_tensor(*law_, k);
    out.js[m] = k.js;
    out.i1[m] = k.i1;
    out.i2[m] = k.i2;
    out.lambda1[m] = p.lambda1;
    out.lambda2[m] = p.lambda2;
    out.stretch_dir1.col(m) = p.stretch_dir1;
    out.stretch_dir2.col(m) = p.stretch_dir2;
    out.tension1[m] = p.tension1;
    out.tension2[m] = p.tension2;
    out.tension_dir1.col(m) = p.tension_dir1;
    out.tension_dir2.col(m) = p.tension_dir2;
    out.energy_density[m] = law_->energy(k.i1, k.i2).w;
  }
  return out;
}

double Membrane::energy(const Matrix3Xd& x) const {
  Matrix3Xd t1, t2;
  current_tangents(x, &t1, &t2);
  const MatrixXd q1 = geometry::to_gauss(mesh_, MatrixXd(t1), interp_);
  const MatrixXd q2 = geometry::to_gauss(mesh_, MatrixXd(t2), interp_);
  double total = 0.0;
  for (int k = 0; k < q1.cols(); ++k) {
    const Vector3d a1 = q1.col(k), a2 = q2.col(k);
    const double g11 = a1.dot(a1), g12 = a1.dot(a2), g22 = a2.dot(a2);
    const double sg = std::sqrt(g11 * g22 - g12 * g12);
    check_area(sg);
    const double js = sg / qsqrt_g_[k];
    const double i1 = qgi11_[k] * g11 + 2.0 * qgi12_[k] * g12 + qgi22_[k] * g22 - 2.0;
    total += qweight_[k] * qsqrt_g_[k] * law_->energy(i1, js * js - 1.0).w;
  }
  return total;
}

}  // namespace capflow::membrane
