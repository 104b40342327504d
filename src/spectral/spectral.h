// capflow/spectral: one-dimensional spectral toolkit on [-1, 1].
//
//  * Gauss-Legendre rule, n points: exact for polynomials of degree <= 2n-1.
//  * Gauss-Lobatto rule, n points (both ends included): exact for degree <= 2n-3.
//    Nodes and weights come from Newton iteration on Legendre polynomials (no tables);
//    any n in [1, 256] (Lobatto: [2, 256]) is accepted.
//  * Barycentric Lagrange interpolation through arbitrary distinct nodes x_0..x_{n-1}:
//      p(t) = sum_j w_j/(t-x_j) f_j / sum_j w_j/(t-x_j),  w_j = 1/prod_{k!=j}(x_j-x_k)
//    interpolation_matrix(nodes, t) maps nodal values to values at the targets t, and
//    differentiation_matrix(nodes) maps nodal values to nodal values of p' (both exact for
//    polynomials of degree <= n-1).
//  * Tensor-product evaluation on [-1,1]^2 of values v(i,j) at (x_i, x_j).
//
// Failure modes: invalid arguments (n out of range, coincident nodes) throw
// std::invalid_argument; these are programming errors, not user errors.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace capflow::spectral {

using Eigen::MatrixXd;
using Eigen::VectorXd;

struct Rule {
  VectorXd x;  // nodes, ascending
  VectorXd w;  // weights, sum = 2
};

// Legendre polynomial P_n(x) and its derivative, by the three-term recurrence.
void legendre(int n, double x, double* p, double* dp);

Rule gauss_legendre(int n);
Rule gauss_lobatto(int n);

// Barycentric weights (scaled so that max |w| = 1).
VectorXd barycentric_weights(const VectorXd& nodes);

// Lagrange basis l_j(t), and its derivative l_j'(t), for all j at one point t.
// bw: barycentric_weights(nodes). dl may be nullptr. Exact at the nodes (returns unit vectors).
void lagrange_basis(const VectorXd& nodes, const VectorXd& bw, double t, double* l, double* dl);

// Lagrange bases at many points, product form: l_j(t) = c_j prod_{k != j} (t - x_k) with
// c = product_weights(nodes) (c_j = 1/prod_{k != j} (x_j - x_k), unscaled), and l_j'(t) from
// prefix and suffix products and their derivatives. No divisions and no special case at or
// near a node (accurate to ~1e-14 everywhere in [-1, 1]: tests/spectral). Output column-major
// with leading dimension ld >= np: L[p + j ld] = l_j(t[p]), dL[p + j ld] = l_j'(t[p]).
// Vectorised over the points (scratch: 4 np doubles, thread-local).
VectorXd product_weights(const VectorXd& nodes);
void lagrange_bases(const VectorXd& nodes, const VectorXd& c, const double* t, int np, double* L,
                    double* dL, long ld);

// Row k holds l_j(targets[k]): values_at_targets = M * nodal_values.
MatrixXd interpolation_matrix(const VectorXd& nodes, const VectorXd& targets);
// Row k holds l_j'(targets[k]).
MatrixXd derivative_matrix(const VectorXd& nodes, const VectorXd& targets);
// D(i, j) = l_j'(x_i): nodal derivative = D * nodal_values (rows sum to zero exactly).
MatrixXd differentiation_matrix(const VectorXd& nodes);

// Chebyshev coefficients of the interpolant through the nodes: with C = chebyshev_matrix(nodes)
// (n x n), p(t) = sum_j v_j l_j(t) = sum_k c_k T_k(t) for c = C v (row k, column j holds the k-th
// Chebyshev coefficient of l_j). Built by n-point Gauss-Chebyshev quadrature, exact for these
// polynomials (degree <= 2n - 2), no matrix inversion.
MatrixXd chebyshev_matrix(const VectorXd& nodes);

// Tensor-product value at (s, t) of v(i, j) given at (nodes_i, nodes_j):
//   p(s, t) = sum_ij v(i, j) l_i(s) l_j(t).
double tensor_evaluate(const VectorXd& nodes, const MatrixXd& v, double s, double t);
// Values at all target pairs: result(a, b) = p(sa[a], tb[b]).
MatrixXd tensor_resample(const VectorXd& nodes, const MatrixXd& v, const VectorXd& sa,
                         const VectorXd& tb);

}  // namespace capflow::spectral
