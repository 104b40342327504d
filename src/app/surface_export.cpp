#include "app/surface_export.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "app/surface_files.h"
#include "geometry/surface.h"
#include "spectral/spectral.h"

namespace capflow::app {

using Eigen::MatrixXd;

namespace {

// Interpolation from the nb nodes of one element to its n x n points: out(a, b) = sum_ij
// L(a, i) v(i, j) M(b, j) for the nodal values v(i, j) of row r of f (i along xi, j along eta).
class ElementResampler {
 public:
  ElementResampler(const geometry::Mesh& mesh, int n) : nb_(mesh.nb()), n_(n) {
    const Eigen::VectorXd t = spectral::gauss_lobatto(n).x;
    I_ = spectral::interpolation_matrix(mesh.nodes(), t);
    D_ = spectral::derivative_matrix(mesh.nodes(), t);
  }
  // Values (which = 0), xi-derivatives (1) or eta-derivatives (2) of row r of f on element e.
  MatrixXd operator()(const Eigen::MatrixXd& f, int r, int e, int which) const {
    MatrixXd v(nb_, nb_);
    for (int j = 0; j < nb_; ++j)
      for (int i = 0; i < nb_; ++i) v(i, j) = f(r, (e * nb_ + j) * nb_ + i);
    const MatrixXd& A = which == 1 ? D_ : I_;
    const MatrixXd& B = which == 2 ? D_ : I_;
    return A * v * B.transpose();
  }
  int n() const { return n_; }

 private:
  int nb_, n_;
  MatrixXd I_, D_;  // n x nb: l_i and l_i' at the n Gauss-Lobatto points
};

// Row-vector field (1 x num_local) from a std::vector.
MatrixXd row(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::RowVectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// The field f (rows x num_local) on the n x n points of every element, tuple-major.
std::vector<double> resample(const ElementResampler& rs, const MatrixXd& f, int ne) {
  const int n = rs.n(), c = static_cast<int>(f.rows());
  std::vector<double> out(static_cast<size_t>(ne) * n * n * c);
  for (int e = 0; e < ne; ++e)
    for (int r = 0; r < c; ++r) {
      const MatrixXd v = rs(f, r, e, 0);
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a)
          out[((static_cast<size_t>(e) * n + b) * n + a) * c + r] = v(a, b);
    }
  return out;
}

}  // namespace

output::VtkSurface surface_export(const geometry::Mesh& mesh, const NodalState& s, int n) {
  if (n < 2)
    throw std::invalid_argument("surface_export: n must be >= 2, got " + std::to_string(n));
  const int ne = mesh.ne(), nl = mesh.num_local();
  if (!s.x || !s.snapshot || s.x->cols() != nl || (s.velocity && s.velocity->cols() != nl) ||
      (s.bending_energy && s.bending_energy->size() != nl))
    throw std::invalid_argument(
        "surface_export: the positions, velocity or snapshot do not fit the mesh");
  const render::Snapshot& sn = *s.snapshot;
  const ElementResampler rs(mesh, n);
  output::VtkSurface v;
  v.ne = ne;
  v.n = n;
  v.time = sn.time;
  const MatrixXd x = *s.x;
  v.x = resample(rs, x, ne);
  // the interpolant's unit normal at each point (outward for the outward element maps)
  std::vector<double> normals(v.x.size());
  for (int e = 0; e < ne; ++e) {
    MatrixXd xs[3], xt[3];
    for (int r = 0; r < 3; ++r) {
      xs[r] = rs(x, r, e, 1);
      xt[r] = rs(x, r, e, 2);
    }
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const Eigen::Vector3d p(xs[0](a, b), xs[1](a, b), xs[2](a, b));
        const Eigen::Vector3d q(xt[0](a, b), xt[1](a, b), xt[2](a, b));
        const Eigen::Vector3d m = p.cross(q).normalized();
        const size_t k = (static_cast<size_t>(e) * n + b) * n + a;
        for (int d = 0; d < 3; ++d) normals[3 * k + d] = m[d];
      }
  }
  v.point_arrays["Normals"] = {3, std::move(normals)};
  if (!sn.tau1.empty()) {
    v.point_arrays["tau1"] = {1, resample(rs, row(sn.tau1), ne)};
    v.point_arrays["tau2"] = {1, resample(rs, row(sn.tau2), ne)};
  }
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh, *s.x);
  v.point_arrays["mean_curvature"] = {1, resample(rs, g.mean_curvature.transpose(), ne)};
  if (s.velocity) v.point_arrays["velocity"] = {3, resample(rs, *s.velocity, ne)};
  if (s.bending_energy)
    v.point_arrays["bending_energy_density"] = {1, resample(rs, s.bending_energy->transpose(), ne)};
  v.field_scalars = snapshot_field_scalars(sn);
  return v;
}

}  // namespace capflow::app
