// capflow/geometry/smoothing: the paper's first-order membrane smoothing (sec. 3.2, eqs. 17-21).
//
// A field F (the node positions x, or the traction jump f) is made continuous with its first
// derivatives across element edges:
//   1. F at coincident nodes is replaced by its average over the coincidence class (eq. 17).
//   2. At every edge/corner node, the tensor M = sum_a E^a (x) dF/dtheta_a is formed from the
//      node's own element and averaged over the class (eq. 18 / 20). For the geometry
//      E^a = T^a (reference reciprocal tangents), so M^T is the surface deformation gradient
//      A = t_a T^a; for the traction E^a = t^a (current reciprocal tangents), M = grad_s f.
//   3. The new cross-edge derivatives are dF/dtheta_a = M_avg^T E_a (eq. 19 / 21), E_a the
//      covariant tangents matching E^a (E_a . E^b = delta).
//   4. Reconstruction, reading (b) of method.md: the element stays a degree NB-1 Lagrange
//      interpolant; nodal values are re-solved only next to the element edges:
//      (i)  each element edge is a grid line with end slopes (along the edge) prescribed at its
//           two corners: the two edge nodes next to the corners are re-solved (2x2 system). It
//           uses only data on the edge, so neighbours sharing the edge get the same edge.
//      (ii) with the edges fixed, the ring of nodes next to the edges is re-solved so that the
//           interpolant's cross-edge slopes at every edge-interior node equal the prescribed ones
//           (slopes first corrected for the along-edge change of (i)). Near the corners the
//           prescribed slopes are not always compatible with a degree NB-1 interpolant whose
//           edges are fixed, so this is a least-squares solve; the residual jump shrinks with
//           every application (measured: 48x after one application, 5000x after 20, on a random
//           O(1e-3) kink; tests/geometry/test_smoothing.cpp). The operator depends only on NB.
//      Coincident nodes are averaged again at the end so shared nodes are bit-identical.
// Why reading (b): the surface stays a plain Lagrange interpolant, so every other module (membrane
// mechanics, quadrature, diagnostics, renderer) needs no Hermite representation. On data that is
// already C1 the operation is the identity up to round-off.
// Cost: O(NE NB^2) per call.
#pragma once

#include <Eigen/Dense>

#include "geometry/mesh.h"

namespace capflow::geometry {

struct SmoothingBasis {
  Matrix3Xd lower1, lower2;  // E_a at every local node
  Matrix3Xd upper1, upper2;  // E^a at every local node (E_a . E^b = delta_ab)
};

// E_a = T_a and E^a = T^a of the surface x (used with the reference sphere for geometry, and
// with the current surface for the traction).
SmoothingBasis tangent_basis(const Mesh& mesh, const Matrix3Xd& x);
// E_a = t_a given at every local node (e.g. Hermite-smoothed tangents) and their reciprocals.
SmoothingBasis basis_from_tangents(const Matrix3Xd& t1, const Matrix3Xd& t2);

// Averages F over every coincidence class (eq. 17).
void average_coincident(const Mesh& mesh, Matrix3Xd* f);

// First-order smoothing of F in place (steps 1-4 above).
void smooth_first_order(const Mesh& mesh, const SmoothingBasis& basis, Matrix3Xd* f);

// Reading (a) of method.md: the first-order smoothed DERIVATIVES of F, nodal values unchanged.
// Along every grid line the 1-D Hermite interpolant of degree NB+1 through the NB nodal values
// and the two prescribed end slopes (steps 2-3) is
//   H(xi) = L(xi) + w(xi) [(1-xi)/2 c- + (1+xi)/2 c+],  w = prod_k (xi - xi_k),
//   c+- = (s+- - L'(+-1)) / w'(+-1);
// d1 (d2) receive H' at the nodes of the lines along xi (eta). At the edge nodes d1/d2 equal
// the prescribed slopes exactly, so they are the same tensor in every element sharing the node.
// F itself must already be continuous (average_coincident).
void hermite_derivatives(const Mesh& mesh, const SmoothingBasis& basis, const Matrix3Xd& f,
                         Matrix3Xd* d1, Matrix3Xd* d2);

// Largest jump, over shared edge/corner nodes, of the tensor M of step 2 between the elements
// sharing the node (a measure of first-order discontinuity; 0 for C1 data).
double max_gradient_jump(const Mesh& mesh, const SmoothingBasis& basis, const Matrix3Xd& f);

}  // namespace capflow::capsule
