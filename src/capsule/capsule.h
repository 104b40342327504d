// capflow/capsule/capsule: the capsule's state and its time evolution (paper secs. 2-3).
//
// Velocity of the membrane nodes for viscosity ratio lambda = 1 (paper eq. 5, dimensionless):
//   u(x0) = u_inf(x0) - (1/(8 pi Ca)) INT S(x0, x) . f(x) dS(x),
// f = -div_s tau the traction jump from the membrane (units Gs/a), lengths in a, time in 1/G.
// Time stepping: classical RK4 on the node positions (material points, dx/dt = u) with a fixed
// dt (step), or any integrator that evaluates velocity() and ends each step with finish_step
// and accept_step; Ca may depend on time (evaluated at the stage times).
// Smoothing (paper sec. 3.2, geometry/smoothing.h): f is smoothed every time it is computed
// (i.e. at the start of each RK stage, with the current tangents), the geometry at the end of
// every step (with the reference tangents).
// Optional volume correction (paper eq. 23), off by default:
//   x_new - x_c = (V0/V)^(1/3) (x - x_c).
// Symmetry: planar extension evaluates the velocity on one octant, simple shear on a quarter
// (capsule/symmetry.h); results equal the full evaluation to round-off (tests/capsule).
// Threads: the boundary integral loops use OpenMP; a Capsule object is not thread-safe.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <vector>

#include "capsule/flow.h"
#include "capsule/symmetry.h"
#include "capsule/viscosity_ratio.h"
#include "geometry/mesh.h"
#include "geometry/reference_shape.h"
#include "geometry/smoothing.h"
#include "membrane/bending.h"
#include "membrane/law.h"
#include "membrane/membrane.h"
#include "stokes/boundary_integral.h"

namespace capflow::capsule {

using geometry::SmoothingBasis;
using geometry::average_coincident;
using geometry::hermite_derivatives;
using geometry::smooth_first_order;
using geometry::tangent_basis;

using CaFunction = std::function<double(double t)>;

enum class SymmetryChoice { Auto, None };

// How the paper's first-order smoothing is realised (method.md sec. 6, the two readings):
//   HermiteDerivatives (reading a, default): nodal values are never moved (except the averaging of
//     coincident nodes); the membrane mechanics uses the tangents of the degree NB+1 Hermite
//     interpolant through the nodal values and the averaged edge slopes (hermite_derivatives), and
//     f is averaged over coincident nodes before the boundary integral.
//   NodalReconstruction (reading b): the nodes next to the element edges are re-solved so that
//     the Lagrange interpolant itself has the averaged edge slopes (smooth_first_order), for x
//     after each step and for f before each use. Kept for comparison: it moves material points by
//     the derivative mismatch every step, which measurably drains volume.
enum class SmoothingMethod { HermiteDerivatives, NodalReconstruction };

struct DynamicsOptions {
  // lambda, inner / outer viscosity, in (0, 100]: other than 1, every velocity evaluation
  // solves the second-kind equation of capsule/viscosity_ratio.h by GMRES to krylov_tolerance
  // (relative residual)
  double viscosity_ratio = 1.0;
  double krylov_tolerance = 1e-10;
  bool smooth_geometry = true;  // paper's first-order smoothing of x after each step
  bool smooth_traction = true;  // ... and of f before each use
  SmoothingMethod smoothing = SmoothingMethod::HermiteDerivatives;
  bool volume_correction = false;                  // paper eq. 23
  SymmetryChoice symmetry = SymmetryChoice::Auto;  // Auto: octant (planar ext.), quarter (shear)
  stokes::QuadratureOptions quadrature;
  // Factor on every order of `quadrature` after its defaults are resolved for the mesh
  // (stokes::scale_orders, far = own = near); 1 leaves the rules unchanged.
  double quadrature_scale = 1.0;
  // The stress-free reference shape, also the initial shape (geometry/reference_shape.h).
  geometry::ReferenceShape shape;
  // Bending stiffness (membrane/bending.h): its load adds to the elastic traction.
  membrane::BendingOptions bending;
};

// The rules a Capsule with these options uses: options.quadrature with its defaults resolved for
// the mesh, times options.quadrature_scale (std::invalid_argument outside [1, 4]).
stokes::QuadratureOptions quadrature_rules(const geometry::Mesh& mesh,
                                           const DynamicsOptions& options);

class Capsule {
 public:
  // The mesh must outlive the Capsule. Starts from the reference sphere at t = 0 (smoothed once
  // when smooth_geometry is on; initial_volume() is the volume of that state).
  // Throws std::invalid_argument for invalid law options or viscosity_ratio outside (0, 100].
  Capsule(const geometry::Mesh& mesh, const membrane::LawOptions& law, const Flow& flow,
          const DynamicsOptions& options = {});

  const geometry::Mesh& mesh() const { return mesh_; }
  const Flow& flow() const { return flow_; }
  const DynamicsOptions& options() const { return opt_; }
  const membrane::Membrane& membrane() const { return *membrane_; }
  const SymmetryMap& symmetry() const { return *symmetry_; }
  // The quadrature rules in use: the defaults resolved for the mesh, times quadrature_scale.
  const stokes::QuadratureOptions& quadrature() const { return ops_->options(); }

  const Eigen::Matrix3Xd& positions() const { return x_; }
  double time() const { return t_; }
  long step_count() const { return steps_; }
  double initial_volume() const { return v0_; }
  // Restores a saved state (restart). Throws std::invalid_argument on a size mismatch.
  void set_state(const Eigen::Matrix3Xd& x, double t, long steps);
  // Switches the eq. 23 volume correction on or off mid-run (a live control-file edit); when on,
  // the end of every later step rescales the shape to initial_volume().
  void set_volume_correction(bool on) { opt_.volume_correction = on; }

  // Where velocity() takes the single layer at the targets from: this process's operators by
  // default; the app installs the ranks of an MPI run (app/worker_team.h: the same per-target
  // sums, spread over the ranks), which must give the same values.
  using TargetSum = std::function<void(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& f,
                                       const std::vector<int>& targets, Eigen::Matrix3Xd& out)>;
  void set_single_layer(TargetSum sum) { single_layer_ = std::move(sum); }
  // Likewise the double-layer matrix of the viscosity-ratio solve (lambda != 1) at x, with or
  // without symmetry: by default assembled here; an MPI run's ranks assemble shares of its rows
  // (double_layer_rows), which must give the same matrix.
  using MatrixAssembly = std::function<stokes::RowMat(const Eigen::Matrix3Xd& x, bool symmetry)>;
  void set_double_layer_matrix(MatrixAssembly assemble) { dl_matrix_ = std::move(assemble); }
  // Rows 3 k .. 3 k + 2 of that matrix for k in `rows` (indices into the targets of the
  // symmetric or the unsymmetric map). Throws std::logic_error when viscosity_ratio is 1.
  stokes::RowMat double_layer_rows(const Eigen::Matrix3Xd& x, bool symmetry,
                                   const std::vector<int>& rows) const;
  // The number of targets of the symmetric (the runs') or the unsymmetric map.
  size_t symmetry_targets(bool symmetry) const {
    return (symmetry ? *symmetry_ : *no_symmetry_).targets().size();
  }
  const stokes::BoundaryOperators& operators() const { return *ops_; }

  // Traction jump at positions x, smoothed if options().smooth_traction.
  Eigen::Matrix3Xd traction(const Eigen::Matrix3Xd& x) const;
  // Membrane fields (stretches, tensions) at x, with the same tangents the dynamics uses.
  membrane::MembraneFields fields(const Eigen::Matrix3Xd& x) const;
  // The bending load's owner (membrane/bending.h), null without bending.
  const membrane::Bending* bending() const { return bending_.get(); }
  // The tangents the membrane mechanics sees at x (Hermite-smoothed or Lagrange).
  void tangents(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* t1, Eigen::Matrix3Xd* t2) const;
  // Node velocities at positions x for capillary number ca (> 0).
  Eigen::Matrix3Xd velocity(const Eigen::Matrix3Xd& x, double ca) const;
  // How many times velocity() (or velocity_full) has been evaluated by this object.
  long velocity_evaluations() const { return evaluations_; }
  // GMRES iterations (double-layer applications) of the viscosity-ratio solves so far (0 when
  // viscosity_ratio is 1).
  long krylov_iterations() const { return krylov_iterations_; }
  // The viscosity-ratio solve's warm start at the symmetry targets (empty when viscosity_ratio
  // is 1 or before the first evaluation): stored in checkpoints, so that a resumed run goes on
  // bit for bit. set_krylov_warm_start throws std::invalid_argument for a wrong size.
  Eigen::VectorXd krylov_warm_start() const;
  void set_krylov_warm_start(const Eigen::VectorXd& v);
  // Same, evaluated at every node without symmetry (reference for tests).
  Eigen::Matrix3Xd velocity_full(const Eigen::Matrix3Xd& x, double ca) const;

  // One RK4 step of size dt with Ca(t); then finish_step.
  void step(double dt, const CaFunction& ca);
  // The state one classical RK4 step of size dt after x (at time t, Ca(t) at the stages),
  // finished (finish_step); the capsule's own state is not changed. What step() takes, and the
  // step map of the steady solver and the stability study.
  Eigen::Matrix3Xd rk4_step(const Eigen::Matrix3Xd& x, double t, double dt,
                            const CaFunction& ca) const;
  // The state one explicit midpoint (second-order Runge-Kutta) step of size dt after x, at
  // capillary number ca, finished (finish_step): the step map of the steady solver, at two
  // velocity evaluations.
  Eigen::Matrix3Xd midpoint_step(const Eigen::Matrix3Xd& x, double dt, double ca) const;
  // What ends every step: smoothing of x (options().smooth_geometry) and the optional volume
  // correction. Used by step() and by the adaptive stepper (capsule/adaptive_stepper.h).
  void finish_step(Eigen::Matrix3Xd* x) const;
  // Takes x (already finished) as the state at time t after one more step.
  void accept_step(const Eigen::Matrix3Xd& x, double t);

 private:
  Eigen::Matrix3Xd velocity_impl(const Eigen::Matrix3Xd& x, double ca, bool use_symmetry) const;

  const geometry::Mesh& mesh_;
  Flow flow_;
  DynamicsOptions opt_;
  std::unique_ptr<membrane::Membrane> membrane_;
  std::unique_ptr<membrane::Bending> bending_;  // null without bending
  std::unique_ptr<stokes::BoundaryOperators> ops_;
  std::unique_ptr<SymmetryMap> symmetry_;
  std::unique_ptr<SymmetryMap> no_symmetry_;
  // viscosity_ratio != 1: the second-kind solves on the symmetry targets and on every node (their
  // warm starts change with each evaluation, hence mutable)
  mutable std::unique_ptr<ViscosityRatioSolver> lambda_solver_, lambda_solver_full_;
  SmoothingBasis ref_basis_;
  Eigen::Matrix3Xd x_;
  double t_ = 0;
  long steps_ = 0;
  double v0_ = 0;
  mutable long evaluations_ = 0;
  mutable long krylov_iterations_ = 0;
  TargetSum single_layer_;    // empty: ops_
  MatrixAssembly dl_matrix_;  // empty: the viscosity-ratio solvers assemble
};

// Volume enclosed by the surface x (Gauss quadrature, nq = NB + 4).
double enclosed_volume(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x);

// x scaled about its volume centroid x_c = (1/V) INT (|x|^2/2) n dS to enclose volume v_target
// (paper eq. 23): x_c + (v_target/V)^(1/3) (x - x_c).
Eigen::Matrix3Xd rescale_to_volume(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x,
                                   double v_target);

}  // namespace capflow::capsule
