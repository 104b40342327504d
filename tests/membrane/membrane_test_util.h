// Shared helpers for the membrane tests: test shapes, smooth perturbations, quadratures.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"
#include "membrane/law.h"
#include "membrane/membrane.h"
#include "spectral/spectral.h"

namespace capflow::membrane::testing {

using geometry::Mesh;

// A smooth map with no mirror symmetry and no affine part only (so force/torque balance is not
// a consequence of symmetry): a sheared, bent, rotated ellipsoid.
inline geometry::PointMap skew_map() {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.4, Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  return [R](const Vector3d& p) {
    const double X = p.x(), Y = p.y(), Z = p.z();
    const Vector3d q(1.3 * X + 0.15 * Y * Z + 0.1 * X * X, 0.85 * Y + 0.12 * X * X - 0.05 * Z,
                     0.95 * Z + 0.1 * X * Y + 0.08 * Y * Y * Y);
    return Vector3d(R * q + Vector3d(0.3, -0.2, 0.1));
  };
}

// Smooth random displacement field of the reference position X (same value at coincident
// nodes): dx_c = sum_k a_ck sin(k_c . X + phi_ck), fixed seed.
inline Matrix3Xd smooth_perturbation(const Matrix3Xd& ref, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  struct Mode {
    Vector3d k;
    double a, phi;
  };
  std::vector<Mode> modes[3];
  for (int c = 0; c < 3; ++c)
    for (int m = 0; m < 4; ++m)
      modes[c].push_back({Vector3d(u(gen), u(gen), u(gen)) * 1.5, u(gen), 3.0 * u(gen)});
  Matrix3Xd d(3, ref.cols());
  for (int i = 0; i < ref.cols(); ++i)
    for (int c = 0; c < 3; ++c) {
      double s = 0;
      for (const Mode& m : modes[c]) s += m.a * std::sin(m.k.dot(ref.col(i)) + m.phi);
      d(c, i) = s;
    }
  return d;
}

// INT F dS over the current surface x by Gauss quadrature (nq per direction) of the elementwise
// interpolant of the nodal field F (rows x num_local). Returns one value per row.
inline VectorXd gauss_integral(const Mesh& mesh, const Matrix3Xd& x, const MatrixXd& F, int nq) {
  const geometry::QuadratureSurface q = geometry::sample_gauss(mesh, x, nq);
  const MatrixXd Fq = geometry::to_gauss(mesh, F, q.interp);
  return Fq * q.w;
}

// Nodal Gauss-Lobatto quadrature with each element's own area element: sum w_i w_j sqrt(g) F.
inline MatrixXd lobatto_weights(const Mesh& mesh, const Matrix3Xd& x) {
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh, x);
  const spectral::Rule r = spectral::gauss_lobatto(mesh.nb());
  VectorXd w(mesh.num_local());
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 0; j < mesh.nb(); ++j)
      for (int i = 0; i < mesh.nb(); ++i) {
        const int m = mesh.local(e, i, j);
        w[m] = r.w[i] * r.w[j] * g.jac[m];
      }
  return w;
}

// Field values at parameter point (s, t) of every element: rows x ne.
inline MatrixXd eval_in_elements(const Mesh& mesh, const MatrixXd& F, double s, double t) {
  const int nb = mesh.nb();
  MatrixXd out(F.rows(), mesh.ne());
  MatrixXd v(nb, nb);
  for (int e = 0; e < mesh.ne(); ++e)
    for (int r = 0; r < F.rows(); ++r) {
      for (int j = 0; j < nb; ++j)
        for (int i = 0; i < nb; ++i) v(i, j) = F(r, mesh.local(e, i, j));
      out(r, e) = spectral::tensor_evaluate(mesh.nodes(), v, s, t);
    }
  return out;
}

// dE(x + eps dx)/deps at eps = 0, 4th-order central difference with h = 1e-4 (truncation
// ~h^4, round-off ~1e-16/h relative).
inline double energy_derivative(const Membrane& mem, const Matrix3Xd& x, const Matrix3Xd& dx) {
  const double h = 1e-4;
  auto e = [&](double s) { return mem.energy(x + s * dx); };
  return (8.0 * (e(h) - e(-h)) - (e(2 * h) - e(-2 * h))) / (12.0 * h);
}

inline std::vector<std::shared_ptr<const Law>> all_laws() {
  return {std::make_shared<NeoHookeanLaw>(), std::make_shared<SkalakLaw>(1.0),
          std::make_shared<SkalakLaw>(10.0), std::make_shared<MooneyRivlinLaw>(0.5),
          std::make_shared<MooneyRivlinLaw>(0.0)};
}

inline std::string label(const Law& law) {
  if (auto* s = dynamic_cast<const SkalakLaw*>(&law)) return "skalak C=" + std::to_string(s->c());
  if (auto* m = dynamic_cast<const MooneyRivlinLaw*>(&law))
    return "mooney-rivlin psi=" + std::to_string(m->psi());
  return law.name();
}

}  // namespace capflow::membrane::testing
