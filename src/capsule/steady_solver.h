// capflow/capsule/steady_solver: steady shapes in pure straining flows, found as roots.
//
// In a flow with a symmetric velocity gradient a steady capsule's membrane is at rest, so its
// shape is a root of the node velocities, u(X; Ca) = 0 (method.md sec. 9). The root is found as
// a fixed point of the time stepper instead of u itself ("time-stepper based Newton-Krylov"):
//     F(y) = (P(Phi_h(E y)) - E y)|targets / h,
// y the positions of the symmetry-reduced node set (capsule/symmetry.h: the targets), E their
// expansion to every node, Phi_h one explicit midpoint (second-order Runge-Kutta) step of size h
// with the capsule's end-of-step smoothing, P the rescaling about the centroid to the reference
// volume (the volume family of steady states is removed: the volume leak of the discretisation
// is absorbed by P as the bordering unknown p of method.md would). F ~ u at the targets for small
// h; its Jacobian is (R(h J) - 1)/h with R(z) = 1 + z + z^2/2 the midpoint stability function:
// for h near the stability limit (z in [-2, 0] on the real axis) the stiff membrane modes, which
// make GMRES on J itself crawl, are mapped into a bounded cluster (|R(z) - 1|/h <= 1/(2h)), and
// GMRES only has to resolve the few slow shape modes. The classical RK4 step clusters them as
// well, with the same GMRES iterations per state (measured along the neo-Hookean branch, NE=10
// NB=10, Ca 0.25 -> 0.4), at four velocity evaluations per Jacobian-vector product instead of two;
// the forward Euler step (R(z) - 1)/h = lambda, J itself, needs ~1.6x the iterations.
// Newton's method with a line search and GMRES (SUNDIALS KINSOL, SPGMR, difference-quotient
// Jacobian-vector products) solves F = 0 to `tolerance` in the max norm.
// Ca is a parameter: the steady state does not depend on the viscosity ratio (method.md sec. 9).
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <string>

#include "capsule/capsule.h"
#include "capsule/continuation.h"

namespace capflow::capsule {

struct SteadySolveOptions {
  double step = 0;          // h of the midpoint map (> 0): about 0.5x the adaptive steps at the
                            // stability limit (the midpoint step's real interval, [-2, 0], is 0.54x
                            // that of the Cash-Karp pair the adaptive steps use)
  double tolerance = 1e-7;  // max |F| at the root (velocity units, a G)
  int max_newton = 30;
  int max_krylov = 100;                     // GMRES subspace per Newton step (one restart allowed)
  const std::atomic<bool>* stop = nullptr;  // when set, the solve ends at the next evaluation
};

struct SteadySolution {
  Eigen::Matrix3Xd x;  // the last iterate (every node)
  double ca = 0;       // its Ca (the given one, or the hyperplane solve's)
  bool converged = false;
  double residual = 0;   // max |F| at x
  double speed = 0;      // max |u| at x (includes the volume leak's slow dilation)
  int newton = 0;        // Newton iterations
  long krylov = 0;       // GMRES iterations
  long evaluations = 0;  // velocity evaluations
  std::string message;   // why it stopped
};

// Solves from x0 at capillary number ca. `cap` provides the mesh, the law, the flow, the
// smoothing, the symmetry and the reference volume (its own state is not changed).
SteadySolution solve_steady(const Capsule& cap, const Eigen::Matrix3Xd& x0, double ca,
                            const SteadySolveOptions& options);

// The continuation's corrector (capsule/continuation.h): the steady state (x, Ca) on the
// hyperplane <normal, (x, Ca) - predicted> = 0, Ca an unknown; predicted.y and normal.y are the
// positions of every node (3 x N, column-major). The equations are F(y; Ca) = 0 and the
// hyperplane's (same tolerance).
SteadySolution solve_steady_on_hyperplane(const Capsule& cap, const BranchPoint& predicted,
                                          const BranchPoint& normal,
                                          const SteadySolveOptions& options);

// True when the flow's velocity gradient is symmetric (a pure straining flow), in which steady
// membranes are at rest; simple shear and other rotational flows are not.
bool is_pure_straining(const Eigen::Matrix3d& gradient);

}  // namespace capflow::capsule
