// capflow/membrane/bending: the membrane's bending load (method.md sec. 10).
//
// Energy (Helfrich, with a spontaneous curvature c0 that may vary over the material):
//   W_b = (kappa_b / 2) INT (2H - c0)^2 dA,      H = -(1/2) g^ab b_ab (+1/a on a sphere),
// kappa_b = Eb in units of Gs a^2. Two models:
//   helfrich   c0 uniform (default 0);
//   reference  c0 = 2 H_ref at each material point: bending about the reference shape's own
//              curvature (shape memory), so the reference shape is free of bending stress.
// The load, in the convention of the elastic traction (membrane.h: dW = + INT f.dx dS, the load
// the fluid must exert), from the first variation of W_b under a normal displacement psi n and,
// for a c0 carried by the material, a tangential one:
//   f_b = kappa_b [ -Lap_s(2H - c0) - (2H - c0)(2H^2 - 2K + c0 H) ] n + kappa_b (2H - c0) grad_s c0.
// For c0 = 0 this is -2 kappa_b [Lap_s H + 2H(H^2 - K)] n: minus the force the membrane exerts.
// Linearised about the unit sphere, r = 1 + eps Y_l gives f_b.n = kappa_b (l-1) l (l+1) (l+2)
// eps Y_l (24 for l = 2) with c0 = 0, and kappa_b (l-1)^2 (l+2)^2 eps Y_l (16 for l = 2) with
// c0 = 2 (the reference model on the sphere).
//
// Spectral evaluation, fourth derivatives of x in all, with the paper's care at element edges:
//   1. the tangents t_a are the first-order smoothed (Hermite, reading a) derivatives of x through
//      the reference basis, as the elastic traction uses them (geometry/smoothing.h): the same
//      tensor in every element sharing a node, so a slope mismatch of the Lagrange interpolants
//      at the edges does not reach the curvature;
//   2. b_ab = n . d_b t_a from each element's interpolant of those tangents; H, K averaged over
//      coincident nodes (they differ there by the discretisation error only);
//   3. Lap_s(2H - c0) as the divergence of the surface gradient, the gradient averaged over
//      coincident nodes before its divergence is taken; the load averaged again.
// Taking H from the raw Lagrange interpolants instead (step 1 without smoothing) leaves an edge
// kink visible to the fourth-derivative load: a red cell in shear grew waves along the element
// edges at NB = 10 and a tension spike at a three-element corner at NB = 12 that way. Converges
// exponentially in NB on smooth shapes (tests/membrane/test_bending.cpp).
#pragma once

#include <Eigen/Dense>

#include "geometry/mesh.h"
#include "geometry/smoothing.h"

namespace capflow::membrane {

enum class BendingModel { Helfrich, Reference };

struct BendingOptions {
  double modulus = 0;  // Eb = kappa_b / (Gs a^2), >= 0 (0: no bending)
  BendingModel model = BendingModel::Helfrich;
  double c0 = 0;       // helfrich: the spontaneous curvature (1/a)
  bool enabled() const { return modulus > 0; }
};

// The surface's differential geometry at the nodes, every derivative taken with the paper's
// averaged edge slopes (geometry/smoothing.h, reading a): the tangents of x through the reference
// basis, then the normal's gradient (the curvature tensor) through the current one, so that H and
// K are the same in every element sharing a node without moving any nodal value.
struct BendingGeometry {
  geometry::SmoothingBasis basis;  // the smoothed tangents t_a and their reciprocals t^a
  Eigen::Matrix3Xd n;              // unit outward normal
  Eigen::VectorXd jac, H, K;       // sqrt(g), mean (+1/a on the sphere) and Gaussian curvature
};
BendingGeometry bending_geometry(const geometry::Mesh& mesh,
                                 const geometry::SmoothingBasis& ref_basis,
                                 const Eigen::Matrix3Xd& x);

class Bending {
 public:
  // `reference`: the reference nodes (the reference model's c0 = 2 H_ref there).
  Bending(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& reference,
          const BendingOptions& options);
  const BendingOptions& options() const { return opt_; }
  // The load f_b at every local node (3 x num_local), continuous across element edges.
  Eigen::Matrix3Xd load(const Eigen::Matrix3Xd& x) const;
  // W_b by the nodes' Gauss-Lobatto quadrature of each element.
  double energy(const Eigen::Matrix3Xd& x) const;
  // The energy density (kappa_b / 2) (2H - c0)^2 at every local node (Gs; continuous across
  // element edges): what the ParaView surfaces write as bending_energy_density.
  Eigen::VectorXd energy_density(const Eigen::Matrix3Xd& x) const;
  // The nodal spontaneous curvature c0 (num_local).
  const Eigen::VectorXd& c0() const { return c0_; }

 private:
  const geometry::Mesh& mesh_;
  BendingOptions opt_;
  geometry::SmoothingBasis ref_basis_;  // the reference's tangents (as the capsule's smoothing)
  Eigen::VectorXd c0_;
};

// Values at coincident nodes replaced by their mean (each class of the mesh).
Eigen::VectorXd average_over_classes(const geometry::Mesh& mesh, const Eigen::VectorXd& v);

}  // namespace capflow::membrane
