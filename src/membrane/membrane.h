// capflow/membrane/membrane: membrane kinematics, tensions and the traction jump f
// (paper eqs. 8-13, docs method.md section 5).
//
// Kinematics at a point, from reference tangents T_a and current tangents t_a = dx/dtheta_a:
//   T^a = G^ab T_b (reciprocal, T_a.T^b = delta),  A = t_a (x) T^a,  B = A A^T = G^ab t_a (x) t_b,
//   Js = l1 l2 = sqrt(g)/sqrt(G),  I1 = tr B - 2 = G^ab g_ab - 2,  I2 = Js^2 - 1,
//   P = I - n n (current outward normal n = t1 x t2/|t1 x t2|).
// Principal stretches l1 >= l2: the square roots of the two nonzero eigenvalues of B (l2 is
// taken as Js/l1 for accuracy); principal directions: the unit eigenvectors (tangent).
// Tensions (units of Gs): tau = cb B + cp P from the law (law.h); principal tensions
// tau_a = cp + cb l_a^2, reported sorted tension1 >= tension2 with their own directions.
//
// Traction jump (conservative form; the membrane load from the fluid, f = n.(sigma_out -
// sigma_in) = -div_s tau, paper eq. 8):
//   q^a = sqrt(g) tau.t^a = sqrt(g) (cb G^ab + cp g^ab) t_b,
//   f = -(1/sqrt(g)) (d q^1/dxi + d q^2/deta),
// with d/dxi, d/deta the element's Lagrange differentiation matrix. Every local node gets the
// value of its own element (shared nodes are not averaged here).
// Sign: for a virtual displacement dx, dE = + INT f.dx dS (E = total strain energy); the
// elastic force the membrane exerts on the fluid is -f.
//
// Strain energy E = INT w dS_ref, evaluated by nq x nq Gauss-Legendre points per element on
// the reference interpolant, with B and Js recomputed from the interpolated tangents there.
//
// Ownership: Membrane keeps a reference to the Mesh (which must outlive it) and shares the
// Law. Failure modes: a non-finite or zero current area element (degenerate/collapsed
// surface) makes traction/fields/energy throw std::domain_error; size mismatches throw
// std::invalid_argument.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "geometry/mesh.h"
#include "membrane/law.h"

namespace capflow::membrane {

using Eigen::Matrix3d;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

struct PointKinematics {
  Matrix3d A, B, P;
  Vector3d n;
  double js = 1, i1 = 0, i2 = 0;
};

// Kinematics from reference tangents (T1, T2) and current tangents (t1, t2).
PointKinematics point_kinematics(const Vector3d& T1, const Vector3d& T2, const Vector3d& t1,
                                 const Vector3d& t2);
// tau = cb B + cp P (Cartesian form), units of Gs times law.gs().
Matrix3d tension_tensor(const Law& law, const PointKinematics& k);

struct PointPrincipal {
  double lambda1 = 1, lambda2 = 1;  // lambda1 >= lambda2
  Vector3d stretch_dir1, stretch_dir2;
  double tension1 = 0, tension2 = 0;  // tension1 >= tension2
  Vector3d tension_dir1, tension_dir2;
};
PointPrincipal point_principal(const Law& law, const PointKinematics& k);

// Per-node fields for output and diagnostics (every local node, own element's tangents).
struct MembraneFields {
  std::vector<Matrix3d> A, B, tau;
  VectorXd js, i1, i2;
  VectorXd lambda1, lambda2;  // principal stretches, lambda1 >= lambda2
  Matrix3Xd stretch_dir1, stretch_dir2;
  VectorXd tension1, tension2;  // principal tensions, tension1 >= tension2
  Matrix3Xd tension_dir1, tension_dir2;
  VectorXd energy_density;  // w per reference area
};

class Membrane {
 public:
  // reference: 3 x num_local reference node positions (usually mesh.reference()).
  // nq: Gauss points per direction for the energy integral (0 -> nb + 4).
  Membrane(const geometry::Mesh& mesh, const Matrix3Xd& reference, std::shared_ptr<const Law> law,
           int nq = 0);
  // The same with the reference tangents given at every local node (e.g. the smoothed tangents
  // of the reference, so that an undeformed state seen through the same smoothing is exactly
  // stress-free).
  Membrane(const geometry::Mesh& mesh, const Matrix3Xd& ref_t1, const Matrix3Xd& ref_t2,
           std::shared_ptr<const Law> law, int nq = 0);

  const Law& law() const { return *law_; }
  void set_law(std::shared_ptr<const Law> law);
  const geometry::Mesh& mesh() const { return mesh_; }
  int nq() const { return nq_; }

  // Traction jump f (3 x num_local) at the current node positions x (3 x num_local).
  // f must be pre-sized or is resized; no other per-call allocation beyond small work arrays.
  void traction(const Matrix3Xd& x, Matrix3Xd* f) const;
  Matrix3Xd traction(const Matrix3Xd& x) const;

  MembraneFields fields(const Matrix3Xd& x) const;

  // The same from given current tangents t1 = dx/dxi, t2 = dx/deta at every local node (e.g. the
  // first-order smoothed tangents of the capsule's Hermite representation) instead of the
  // Lagrange derivatives of x.
  void traction_from_tangents(const Matrix3Xd& t1, const Matrix3Xd& t2, Matrix3Xd* f) const;
  MembraneFields fields_from_tangents(const Matrix3Xd& t1, const Matrix3Xd& t2) const;

  // Total strain energy INT w dS_ref (Gauss quadrature on the reference surface).
  double energy(const Matrix3Xd& x) const;

 private:
  void current_tangents(const Matrix3Xd& x, Matrix3Xd* t1, Matrix3Xd* t2) const;

  const geometry::Mesh& mesh_;
  std::shared_ptr<const Law> law_;
  Matrix3Xd ref_t1_, ref_t2_;             // reference tangents at nodes
  VectorXd gi11_, gi12_, gi22_, sqrt_g_;  // reference G^ab and sqrt(G) at nodes
  int nq_;
  MatrixXd interp_;                                     // nq x nb
  VectorXd qgi11_, qgi12_, qgi22_, qsqrt_g_, qweight_;  // at Gauss points; weight = wa wb
};

}  // namespace capflow::membrane
