// capflow/stokes/matrix_sums: the double layer assembled as a matrix (boundary_integral.h,
// double_layer_matrix): at one target x0, its kernel K = -6 (r.n) r r^T / r^5 (times w J) over one
// element summed against the element's nodal bases instead of against a density,
//   E(a + nb b, c) = sum_points K_c(x0, p) L_a(s_p) L_b(t_p),
// c over the 6 entries of the symmetric K in the order xx, yy, zz, xy, xz, yz, and
// total[c] += sum_points K_c (the coefficient of -u(x0)). Then DL[u](x0) over the element is
// sum_nodes K(node) u(node) - K_total u(x0), the same quadrature as the density form.
// Special rules: per line the kernel times the Lagrange bases along the line (made in registers,
// cloned like line_sums; the lines of one edge side by side in the vector lanes), then the bases
// across times these sums in one product per line orientation; far tiers: the kernel at the Gauss
// points contracted with the interpolation matrix in both directions.
#pragma once

#include <Eigen/Dense>

#include "stokes/far_field.h"
#include "stokes/line_rule.h"
#include "stokes/line_sums.h"

namespace capflow::stokes {

// A thread's working memory of the matrix sums (stokes/thread_buffers.h).
struct MatrixWorkspace {
  Eigen::MatrixXd E;      // nb^2 x 6: the element's kernel sums per node
  Eigen::MatrixXd k;      // far points x 6: the kernel at the Gauss points
  Eigen::MatrixXd t;      // nb x 6 nq: the far contraction's first stage
  Eigen::MatrixXd stack;  // 6 nb x nq: its blocks stacked
  Eigen::MatrixXd e;      // 6 nb x nb: the second stage
  RowMat Gt;              // special rules: per line (column) the kernel sums along it
  RowMat Es, Et;  // special rules: the constant-s and constant-t lines' sums times the bases across
};

// Special rule R on the element whose position is loaded in sc.D0 / sc.D1 (load_element with
// K = 3, in the rule's orientation): E (resized to nb^2 x 6, node a + nb b in that orientation)
// and total as above; sign as for line_sum.
void line_matrix(int nb, const LineRule& R, const NodalBasis& basis, double sign,
                 const Eigen::Vector3d& x0, Scratch& sc, MatrixWorkspace& ws, Eigen::MatrixXd& E,
                 double* total);

// Far tier: the element's Gauss points F.d columns [q0, q0 + nq^2) (far_data), I the tier's
// nq x nb interpolation matrix; E in the element's own orientation (node i + nb j).
void far_matrix(const FarData& F, int q0, const Eigen::MatrixXd& I, const Eigen::Vector3d& x0,
                MatrixWorkspace& ws, Eigen::MatrixXd& E, double* total);

}  // namespace capflow::stokes
