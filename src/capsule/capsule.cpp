#include "capsule/capsule.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/surface.h"

namespace capflow::capsule {

namespace {
constexpr double kPi = 3.14159265358979323846;

SymmetryKind symmetry_for(const Flow& flow, SymmetryChoice choice) {
  if (choice == SymmetryChoice::None) return SymmetryKind::None;
  // From the gradient, for every flow: R G = G R for the mirrors R = diag(+-1, +-1, +-1) iff G
  // is diagonal (planar extension: the octant); for the y mirror and the half turn about y iff
  // y decouples, G_xy = G_yx = G_zy = G_yz = 0 (simple shear: the pair).
  const Eigen::Matrix3d& g = flow.gradient;
  const bool y_decoupled = g(0, 1) == 0 && g(1, 0) == 0 && g(2, 1) == 0 && g(1, 2) == 0;
  if (y_decoupled && g(0, 2) == 0 && g(2, 0) == 0) return SymmetryKind::Octant;
  if (y_decoupled) return SymmetryKind::Shear;
  return SymmetryKind::None;
}
}  // namespace

namespace {
// V = (1/3) INT x.n dS on the sampled surface.
double volume_of(const geometry::QuadratureSurface& q) {
  double v = 0;
  for (int k = 0; k < q.x.cols(); ++k) v += q.x.col(k).dot(q.n.col(k)) * q.w[k];
  return v / 3.0;
}
}  // namespace

double enclosed_volume(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  return volume_of(geometry::sample_gauss(mesh, x, mesh.nb() + 4));
}

Eigen::Matrix3Xd rescale_to_volume(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x,
                                   double v_target) {
  // One sampling of the surface for both the volume and the centroid.
  const geometry::QuadratureSurface q = geometry::sample_gauss(mesh, x, mesh.nb() + 4);
  const double v = volume_of(q);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < q.x.cols(); ++k) c += 0.5 * q.x.col(k).squaredNorm() * q.n.col(k) * q.w[k];
  c /= v;
  const double s = std::cbrt(v_target / v);
  return ((x.colwise() - c) * s).colwise() + c;
}

stokes::QuadratureOptions quadrature_rules(const geometry::Mesh& mesh, const DynamicsOptions& o) {
  if (!(o.quadrature_scale >= 1.0 && o.quadrature_scale <= 4.0))
    throw std::invalid_argument("quadrature_scale = " + std::to_string(o.quadrature_scale) +
                                " is out of range: it must be in [1, 4]");
  const stokes::QuadratureOptions q = stokes::resolve_defaults(mesh, o.quadrature);
  const double k = o.quadrature_scale;
  return k == 1.0 ? q : stokes::scale_orders(q, {k, k, k});
}

Capsule::Capsule(const geometry::Mesh& mesh, const membrane::LawOptions& law, const Flow& flow,
                 const DynamicsOptions& options)
    : mesh_(mesh), flow_(flow), opt_(options) {
  const Eigen::Matrix3Xd reference = geometry::reference_positions(mesh, opt_.shape);
  ref_basis_ = tangent_basis(mesh, reference);
  {
    // The membrane's reference tangents are those the dynamics sees for the reference shape,
    // so the undeformed capsule is exactly stress-free.
    Eigen::Matrix3Xd t1, t2;
    tangents(reference, &t1, &t2);
    membrane_ = std::make_unique<membrane::Membrane>(mesh, t1, t2, membrane::make_law(law));
  }
  if (opt_.bending.enabled())
    bending_ = std::make_unique<membrane::Bending>(mesh, reference, opt_.bending);
  ops_ = std::make_unique<stokes::BoundaryOperators>(mesh, quadrature_rules(mesh, opt_));
  symmetry_ = std::make_unique<SymmetryMap>(mesh, symmetry_for(flow_, opt_.symmetry));
  no_symmetry_ = std::make_unique<SymmetryMap>(mesh, SymmetryKind::None);
  if (opt_.viscosity_ratio != 1.0) {  // the solver checks the ratio and the tolerance
    GmresOptions g;
    g.tolerance = opt_.krylov_tolerance;
    lambda_solver_ =
        std::make_unique<ViscosityRatioSolver>(*ops_, *symmetry_, opt_.viscosity_ratio, g);
    lambda_solver_full_ =
        std::make_unique<ViscosityRatioSolver>(*ops_, *no_symmetry_, opt_.viscosity_ratio, g);
  }
  x_ = reference;
  // The nodal sphere is C1 across element edges only to discretisation accuracy; start from its
  // smoothed version so that V0 (and the volume drift) refers to the state actually advanced.
  if (opt_.smooth_geometry && opt_.smoothing == SmoothingMethod::NodalReconstruction)
    smooth_first_order(mesh_, ref_basis_, &x_);
  v0_ = enclosed_volume(mesh, x_);
}

void Capsule::set_state(const Eigen::Matrix3Xd& x, double t, long steps) {
  if (x.cols() != mesh_.num_local())
    throw std::invalid_argument("Capsule::set_state: expected " +
                                std::to_string(mesh_.num_local()) + " nodes, got " +
                                std::to_string(x.cols()));
  x_ = x;
  t_ = t;
  steps_ = steps;
}

void Capsule::tangents(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* t1,
                       Eigen::Matrix3Xd* t2) const {
  if (opt_.smooth_geometry && opt_.smoothing == SmoothingMethod::HermiteDerivatives) {
    hermite_derivatives(mesh_, ref_basis_, x, t1, t2);
  } else {
    const Eigen::MatrixXd xd = x;
    *t1 = geometry::d_xi(mesh_, xd);
    *t2 = geometry::d_eta(mesh_, xd);
  }
}

membrane::MembraneFields Capsule::fields(const Eigen::Matrix3Xd& x) const {
  Eigen::Matrix3Xd t1, t2;
  tangents(x, &t1, &t2);
  return membrane_->fields_from_tangents(t1, t2);
}

Eigen::Matrix3Xd Capsule::traction(const Eigen::Matrix3Xd& x) const {
  Eigen::Matrix3Xd f, t1, t2;
  tangents(x, &t1, &t2);
  membrane_->traction_from_tangents(t1, t2, &f);
  if (opt_.smooth_traction) {
    if (opt_.smoothing == SmoothingMethod::HermiteDerivatives)
      average_coincident(mesh_, &f);  // the Hermite correction of f changes no nodal value
    else
      smooth_first_order(mesh_, tangent_basis(mesh_, x), &f);
  }
  if (bending_) f += bending_->load(x);  // continuous across edges already
  return f;
}

Eigen::Matrix3Xd Capsule::velocity_impl(const Eigen::Matrix3Xd& x, double ca,
                                        bool use_symmetry) const {
  if (!(ca > 0)) throw std::invalid_argument("Capsule::velocity: Ca must be > 0");
  ++evaluations_;
  const SymmetryMap& sym = use_symmetry ? *symmetry_ : *no_symmetry_;
  const std::vector<int>& targets = sym.targets();
  Eigen::Matrix3Xd sl(3, targets.size());
  if (single_layer_)
    single_layer_(x, traction(x), targets, sl);
  else  // the traction made by one thread while the others start on the geometry
    ops_->single_layer(
        x, [&](Eigen::Matrix3Xd& f) { f = traction(x); }, targets, sl);
  const double c = 1.0 / (8.0 * kPi * ca);
  Eigen::Matrix3Xd ut(3, targets.size());
  for (size_t k = 0; k < targets.size(); ++k)
    ut.col(k) = flow_.gradient * x.col(targets[k]) - c * sl.col(k);
  if (opt_.viscosity_ratio != 1.0) {  // ut is the lambda = 1 velocity u1
    GmresResult r;
    ViscosityRatioSolver& solver = use_symmetry ? *lambda_solver_ : *lambda_solver_full_;
    if (dl_matrix_) {
      const stokes::RowMat dl = dl_matrix_(x, use_symmetry);
      ut = solver.solve(x, ut, &r, &dl);
    } else {
      ut = solver.solve(x, ut, &r);
    }
    krylov_iterations_ += r.iterations;
  }
  Eigen::Matrix3Xd u;
  sym.expand(ut, &u);
  return u;
}

stokes::RowMat Capsule::double_layer_rows(const Eigen::Matrix3Xd& x, bool symmetry,
                                          const std::vector<int>& rows) const {
  if (!lambda_solver_) throw std::logic_error("Capsule: no double layer at viscosity_ratio 1");
  return (symmetry ? *lambda_solver_ : *lambda_solver_full_).matrix_rows(x, rows);
}

Eigen::VectorXd Capsule::krylov_warm_start() const {
  return lambda_solver_ ? lambda_solver_->warm_start() : Eigen::VectorXd();
}

void Capsule::set_krylov_warm_start(const Eigen::VectorXd& v) {
  if (lambda_solver_)
    lambda_solver_->set_warm_start(v);
  else if (v.size() != 0)
    throw std::invalid_argument("Capsule: a warm start for viscosity_ratio 1 (no solve)");
}

Eigen::Matrix3Xd Capsule::velocity(const Eigen::Matrix3Xd& x, double ca) const {
  return velocity_impl(x, ca, true);
}

Eigen::Matrix3Xd Capsule::velocity_full(const Eigen::Matrix3Xd& x, double ca) const {
  return velocity_impl(x, ca, false);
}

Eigen::Matrix3Xd Capsule::rk4_step(const Eigen::Matrix3Xd& x0, double t, double dt,
                                   const CaFunction& ca) const {
  const Eigen::Matrix3Xd k1 = velocity(x0, ca(t));
  const Eigen::Matrix3Xd k2 = velocity(x0 + 0.5 * dt * k1, ca(t + 0.5 * dt));
  const Eigen::Matrix3Xd k3 = velocity(x0 + 0.5 * dt * k2, ca(t + 0.5 * dt));
  const Eigen::Matrix3Xd k4 = velocity(x0 + dt * k3, ca(t + dt));
  Eigen::Matrix3Xd x = x0 + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  finish_step(&x);
  return x;
}

Eigen::Matrix3Xd Capsule::midpoint_step(const Eigen::Matrix3Xd& x0, double dt, double ca) const {
  Eigen::Matrix3Xd x = x0 + dt * velocity(x0 + 0.5 * dt * velocity(x0, ca), ca);
  finish_step(&x);
  return x;
}

void Capsule::step(double dt, const CaFunction& ca) {
  const double t = t_;
  accept_step(rk4_step(x_, t, dt, ca), t + dt);
}

void Capsule::finish_step(Eigen::Matrix3Xd* x) const {
  if (opt_.smooth_geometry) {
    if (opt_.smoothing == SmoothingMethod::NodalReconstruction)
      smooth_first_order(mesh_, ref_basis_, x);
    else
      average_coincident(mesh_, x);
  }
  if (opt_.volume_correction) *x = rescale_to_volume(mesh_, *x, v0_);
}

void Capsule::accept_step(const Eigen::Matrix3Xd& x, double t) {
  x_ = x;
  t_ = t;
  ++steps_;
}

}  // namespace capflow::capsule
