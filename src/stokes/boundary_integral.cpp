#include "stokes/boundary_integral.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <memory>
#include <stdexcept>
#include <thread>

#include "geometry/element_search.h"
#include "geometry/surface.h"
#include "spectral/spectral.h"
#include "stokes/operator_call.h"
#include "stokes/thread_cap.h"

namespace capflow::stokes {

using Eigen::Vector3d;
using Eigen::VectorXd;

QuadratureOptions resolve_defaults(const geometry::Mesh& mesh, QuadratureOptions opt) {
  const int nb = mesh.nb();
  if (nb > kMaxNb) throw std::invalid_argument("BoundaryOperators: nb too large");
  // Far order: a capsule's traction carries its full degree nb-1 (it comes from second
  // derivatives of the geometry), so f J is of degree ~3(nb-1) on an element; Gauss with
  // (3nb+19)/2 points integrates that exactly with ~10 points to spare for the kernel. nb + 3
  // (enough for the smooth densities of the sphere identities) left a quarter of the fig. 2b
  // steady-state volume leak and two thirds of the NH Ca=0.4 one at t=17.4
  // (benchmarks/capsule/volume_flux --far-scale; docs/validation.md, 9.2 "The far Gauss order").
  if (opt.nq_far <= 0) opt.nq_far = (3 * nb + 19) / 2;
  // Mid order: 2 nb + 4 left 1e-4 (relative) in SL[f] at the strongly deformed NH Ca=0.4 state
  // (NE=14 NB=10, t=17.4; benchmarks/capsule/quadrature_study), 3 nb + 2 leaves 3e-5.
  if (opt.nq_mid <= 0) opt.nq_mid = 3 * nb + 2;
  // The single layer's near tier can end at 0.1 sizes (0.2 for the double layer) with 4 nb + 4
  // Gauss points beyond: the same accuracy on the sphere identities and the deformed shapes of
  // tests/stokes at 11-24 % less time per call (docs/performance.md).
  if (opt.single_nq_mid <= 0) opt.single_nq_mid = 4 * nb + 4;
  if (!(opt.single_near_factor > 0.0 && opt.near_factor > 0.0 && opt.single_mid_split >= 0.0))
    throw std::invalid_argument("BoundaryOperators: near factors must be positive");
  // Elongated elements (NE=14 rows: 30 x 90 degrees) stretch the sinh-mapped edge coordinate
  // over a longer physical length; with the square-element orders their next-to-edge nodes miss
  // INT T.n = -4 pi I by 8e-8 at NB=12, with these 2.4e-9 (tests/stokes, StokesSphere).
  double aspect = 1.0;
  for (const geometry::Patch& p : mesh.patches()) {
    const double da = std::abs(p.a1 - p.a0), db = std::abs(p.b1 - p.b0);
    aspect = std::max(aspect, std::max(da, db) / std::min(da, db));
  }
  const bool elongated = aspect > 2.05;
  if (opt.n_edge <= 0) opt.n_edge = elongated ? 3 * nb : 2 * nb;
  if (opt.n_radial_inner < 0) opt.n_radial_inner = nb + 2;
  if (opt.n_radial <= 0) opt.n_radial = opt.n_radial_inner > 0 ? nb : nb + 4;
  if (opt.n_edge_near <= 0) opt.n_edge_near = elongated ? 2 * nb : nb + 6;
  if (opt.n_radial_near <= 0) opt.n_radial_near = nb;
  if (opt.n_radial_near_out <= 0) opt.n_radial_near_out = std::max(4, nb - 2);
  if (opt.near_out_panels < 1 || opt.near_out_panels > 8)
    throw std::invalid_argument("BoundaryOperators: near_out_panels must be in 1..8");
  if (!(opt.own_edge_slope >= 0.0))
    throw std::invalid_argument("BoundaryOperators: own_edge_slope must be >= 0");
  if (opt.n_radial_inner > 0 &&
      !(opt.own_split > 0.0 && opt.own_split < 1.0 && opt.own_grading > 0.0))
    throw std::invalid_argument("BoundaryOperators: own_split must be in (0, 1), own_grading > 0");
  if (opt.n_edge > kMaxEdge || opt.n_edge_near > kMaxEdge)
    throw std::invalid_argument("BoundaryOperators: n_edge / n_edge_near > 256");
  return opt;
}

BoundaryOperators::BoundaryOperators(const geometry::Mesh& mesh, QuadratureOptions options)
    : mesh_(mesh),
      opt_(resolve_defaults(mesh, options)),
      prod_w_(spectral::product_weights(mesh.nodes())),
      cheb_(spectral::chebyshev_matrix(mesh.nodes())),
      own_(mesh, opt_, prod_w_) {
  const int nq[3] = {opt_.nq_far, opt_.nq_mid, opt_.single_nq_mid};
  for (int tier = 0; tier < 3; ++tier) far_basis_[tier] = far_basis(mesh.nodes(), nq[tier]);
  near_edge_ = spectral::gauss_legendre(opt_.n_edge_near);
  near_radial_ = spectral::gauss_legendre(opt_.n_radial_near);
  near_radial_out_ = spectral::gauss_legendre(opt_.n_radial_near_out);
  // near rule: 4 edges x n_radial_near x panels (asinh(1/hu) <= asinh(1e14) < 6 * 6) lines
  max_near_lines_ = 4 * (opt_.n_radial_near * 6 + opt_.n_radial_near_out * opt_.near_out_panels);
  max_lines_ = std::max(max_near_lines_, own_.max_lines());
}
template <BoundaryOperators::Mode M>
OperatorStats BoundaryOperators::apply(const Matrix3Xd& x, const Matrix3Xd* dens,
                                       const std::vector<int>* node_targets,
                                       const Matrix3Xd* point_targets, MatrixXd& out,
                                       RowMat* matrix, const NodeExpansion* expansion,
                                       const DensityFn* make_density) const {
  return OperatorCall<M>(*this, x, dens, node_targets, point_targets, out, matrix, expansion,
                         make_density)
      .run();
}

namespace {
std::vector<int> class_representatives(const geometry::Mesh& mesh) {
  std::vector<int> reps;
  reps.reserve(mesh.num_unique());
  for (const auto& c : mesh.classes()) reps.push_back(c.front());
  return reps;
}
Matrix3Xd scatter_classes(const geometry::Mesh& mesh, const MatrixXd& v) {
  Matrix3Xd out(3, mesh.num_local());
  const auto& cls = mesh.classes();
  for (size_t c = 0; c < cls.size(); ++c)
    for (int m : cls[c]) out.col(m) = v.col(static_cast<int>(c));
  return out;
}
void keep(OperatorStats* to, const OperatorStats& s) {
  if (to) *to = s;
}
}  // namespace

Matrix3Xd BoundaryOperators::single_layer(const Matrix3Xd& x, const Matrix3Xd& f,
                                          OperatorStats* stats) const {
  const std::vector<int> reps = class_representatives(mesh_);
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, &f, &reps, nullptr, v));
  return scatter_classes(mesh_, v);
}

void BoundaryOperators::single_layer(const Matrix3Xd& x, const Matrix3Xd& f,
                                     const std::vector<int>& targets, Matrix3Xd& out,
                                     OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, &f, &targets, nullptr, v));
  out = v;
}

void BoundaryOperators::single_layer(const Matrix3Xd& x, const DensityFn& density,
                                     const std::vector<int>& targets, Matrix3Xd& out,
                                     OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, nullptr, &targets, nullptr, v, nullptr, nullptr, &density));
  out = v;
}

Matrix3Xd BoundaryOperators::single_layer_at(const Matrix3Xd& x, const Matrix3Xd& f,
                                             const Matrix3Xd& points, OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, &f, nullptr, &points, v));
  return v;
}

Matrix3Xd BoundaryOperators::double_layer(const Matrix3Xd& x, const Matrix3Xd& u,
                                          OperatorStats* stats) const {
  const std::vector<int> reps = class_representatives(mesh_);
  MatrixXd v;
  keep(stats, apply<Mode::Double>(x, &u, &reps, nullptr, v));
  return scatter_classes(mesh_, v);
}

void BoundaryOperators::double_layer(const Matrix3Xd& x, const Matrix3Xd& u,
                                     const std::vector<int>& targets, Matrix3Xd& out,
                                     OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Double>(x, &u, &targets, nullptr, v));
  out = v;
}

Matrix3Xd BoundaryOperators::single_layer_normal(const Matrix3Xd& x,
                                                 const std::vector<int>& targets) const {
  MatrixXd v;
  apply<Mode::SingleNormal>(x, nullptr, &targets, nullptr, v);
  return v;
}

RowMat BoundaryOperators::double_layer_matrix(const Matrix3Xd& x, const std::vector<int>& targets,
                                              const NodeExpansion* expansion,
                                              OperatorStats* stats) const {
  MatrixXd unused;
  RowMat a;
  keep(stats, apply<Mode::DoubleMatrix>(x, nullptr, &targets, nullptr, unused, &a, expansion));
  return a;
}

MatrixXd BoundaryOperators::double_layer_normal(const Matrix3Xd& x,
                                                const std::vector<int>& targets) const {
  MatrixXd v;
  apply<Mode::DoubleNormal>(x, nullptr, &targets, nullptr, v);
  return v;
}

Matrix3Xd BoundaryOperators::single_layer_gauss(const geometry::Mesh& mesh, const Matrix3Xd& x,
                                                const Matrix3Xd& f, const Matrix3Xd& points,
                                                int nq) {
  const geometry::QuadratureSurface qs = geometry::sample_gauss(mesh, x, nq);
  const MatrixXd fq = geometry::to_gauss(mesh, f, qs.interp);
  Matrix3Xd out(3, points.cols());
#pragma omp parallel for schedule(static) num_threads(team_size())
  for (int k = 0; k < points.cols(); ++k) {
    Vector3d acc = Vector3d::Zero();
    const Vector3d x0 = points.col(k);
    for (int q = 0; q < qs.x.cols(); ++q) {
      const Vector3d r = qs.x.col(q) - x0;
      const double ir = 1.0 / r.norm();
      const Vector3d fv = fq.col(q);
      acc += qs.w[q] * (ir * fv + (ir * ir * ir * r.dot(fv)) * r);
    }
    out.col(k) = acc;
  }
  return out;
}

QuadratureOptions scale_orders(const QuadratureOptions& resolved, const OrderScales& k) {
  if (resolved.nq_far <= 0 || resolved.n_edge <= 0 || resolved.n_edge_near <= 0)
    throw std::invalid_argument(
        "scale_orders: options must be resolved (BoundaryOperators::options())");
  if (!(k.far > 0 && k.own > 0 && k.near > 0 && k.mid >= 0))
    throw std::invalid_argument("scale_orders: factors must be positive");
  QuadratureOptions q = resolved;
  auto up = [](int& n, double f) { n = std::max(2, static_cast<int>(std::lround(n * f))); };
  up(q.nq_far, k.far);
  up(q.nq_mid, k.mid > 0 ? k.mid : k.far);
  up(q.single_nq_mid, k.mid > 0 ? k.mid : k.far);
  up(q.n_edge, k.own);
  if (q.own_edge_base > 0.0) {
    q.own_edge_base *= k.own;
    q.own_edge_slope *= k.own;
  }
  up(q.n_radial, k.own);
  if (q.n_radial_inner > 0) up(q.n_radial_inner, k.own);
  up(q.n_edge_near, k.near);
  up(q.n_radial_near, k.near);
  up(q.n_radial_near_out, k.near);
  return q;
}

}  // namespace capflow::stokes
