// capflow/stokes/line_sums: the kernel sums over the points of a special quadrature rule
// (line_rule.h) on one element: the element's nodal data in the rule's orientation, stage 1 (the
// 1-D interpolation across the lines) and stage 2 (per point, along the line) with the kernel.
// The single layer's hot loops (stage 1, stage 2 + kernel in register blocks of 8 points, as
// vectors of the clone's width, spectral/simd_width.h) are compiled for x86-64-v4, x86-64-v3 and
// the baseline and chosen at load time (spectral/target_clones.h); so are the other modes' stage 2
// loops, which make the Lagrange bases along the line at each point in registers (no point bases
// are stored or read).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "stokes/kernel_mode.h"
#include "stokes/line_rule.h"

namespace capflow::stokes {

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The single layer's stage 1 of one line of a rule made elsewhere (own_lines.h): the line's row
// of A and of B, and the sign of the element's coordinate along the line relative to the rule's.
struct LineRows {
  const double* A;
  const double* B;
  double along;
};

// Per-thread buffers of the kernel sums (kept across calls, see BoundaryOperators::apply).
struct Scratch {
  RowMat D0, D1;  // element data, nb x (K nb): D0(i, k nb + j) = D1(j, k nb + i) = X_k(i, j)
  RowMat A, B;    // stage 1: values / derivative across, per line
  LineRule near;  // the near rule of the (target, element) being summed
  std::vector<LineRows> rows;  // an own rule's lines made by OwnLines (own_lines.h)
};

// The element's 1-D interpolation nodes, their product weights (spectral::product_weights) and
// differentiation matrix (nb x nb, column-major): the Lagrange bases of the modes other than the
// Chebyshev single layer.
struct NodalBasis {
  const double* nodes;
  const double* weights;
  const double* diff;
};

// An element's nodal data for the single layer with the coordinate along the rule lines in
// Chebyshev coefficients (spectral::chebyshev_matrix), made once per element and call: cs row i
// (s-node), column c nb + k = the k-th coefficient in t of X_c(s_i, t); ct row j (t-node),
// column c nb + k = the k-th coefficient in s of X_c(s, t_j) (X_c: x, then the density if K = 6);
// chebyshev_element makes the columns of the components c0 <= c < c1 (0-2 x, 3-5 the density).
// Stage 2 then evaluates T_k and T_k' = k U_{k-1} by their recurrences at each point instead of
// Lagrange bases (no per-point basis evaluation). The other modes keep nodal data and Lagrange
// bases (made in registers at each point, with the along derivative interpolated from the
// nodal derivatives of each line): the double layer's
// r.n cancels to O(r^2) next to the target, and x(p) - x0 keeps its digits there only with bases
// that reproduce the nodal value at the node (in Chebyshev form INT T.n = -4 pi I lost about a
// decade, docs/performance.md).
struct ChebElement {
  RowMat cs, ct;
};
void chebyshev_element(int nb, int c0, int c1, const Eigen::MatrixXd& C, const Eigen::Matrix3Xd& x,
                       const Eigen::Matrix3Xd* dens, int base, ChebElement& ce);
// The data of ce in the orientation of symmetry sym (OwnRules bits: 1 flip s, 2 flip t, 4 swap;
// 0 for the near rules) into sc.D0 / sc.D1, as line_sum<Mode::Single> expects them.
void load_chebyshev(int nb, int K, const ChebElement& ce, int sym, Scratch& sc);

// Element data (x and, if K == 6, the density) in the orientation given by perm (canonical
// (a + nb b) -> local node within the element).
void load_element(int nb, int K, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd* dens, int base,
                  const int* perm, Scratch& sc);

// Sizes a scratch's line buffers A, B (size_lines) and element data D0, D1 (size_scratch, padding
// zeroed) for nb nodes per direction and rules of up to `lines` lines, with padded columns (pad8).
// Buffers that are big enough are kept (size_scratch keeps loaded element data of the same nb).
void size_lines(Scratch& sc, int nb, int lines);
void size_scratch(Scratch& sc, int nb, int lines);

// Stage 1 of rule R: for every line, the 1-D interpolation across the lines of the element data in
// D0 (constant-s lines, the first R.n0) and D1 (the others; sc.D0 / sc.D1, or a ChebElement's cs /
// ct) into sc.A (the first Kn columns: values at the along nodes or along coefficients) and sc.B
// (the first n3: d/d(across) of the position; 0: none); sizes A and B.
void across_lines(int nb, int Kn, int n3, const LineRule& R, const RowMat& D0, const RowMat& D1,
                  Scratch& sc);

// Sum the kernel over the points of one line rule; the element data are in sc.D0/D1 (in the
// rule's orientation: load_element, or load_chebyshev for Mode::Single); sign: orientation of
// the rule's (s, t) relative to the element's.
// Stage 1: for every line, the 1-D interpolation across the lines (dense products
// Lc^T D: lines x (K nb)); stage 2: per point, length-nb dot products along the line.
template <Mode M>
void line_sum(int nb, int K, const LineRule& R, const NodalBasis& basis, double sign,
              const Eigen::Vector3d& x0, const Eigen::Vector3d& u0, Scratch& sc, double* acc);

// Stage 1 of the single layer for nl lines with 1-D bases Lc, dLc (nb x nl, column-major) across
// the lines of D (a ChebElement's cs for lines of constant s, ct for constant t): the lines' rows
// of A (pad8(6 nb) columns, leading dimension ldA) and B (pad8(3 nb), ldB) as across_lines makes
// them.
void single_across(int nb, int nl, const double* Lc, const double* dLc, const RowMat& D, double* A,
                   long ldA, double* B, long ldB);

// The single layer over rule R in the element's own orientation (a near rule), stage 1 reading the
// element's Chebyshev data ce in place (no load_chebyshev); adds to acc[0..2].
void single_sum(int nb, const LineRule& R, const ChebElement& ce, const Eigen::Vector3d& x0,
                Scratch& sc, double* acc);

// Stage 2 of the single layer over the lines of R, each line's stage 1 given by rows[l] (its
// points at the element coordinates rows[l].along * (base + scale off)); adds to acc[0..2].
void single_rows_sum(int nb, const LineRule& R, const LineRows* rows, const Eigen::Vector3d& x0,
                     double* acc);

// Single layer with the product g = J f interpolated from its nodal values (sc.D0/D1 hold x
// and g): 6 values per point instead of 12 (no tangents, no derivative bases).
void line_sum_jf(int nb, const LineRule& R, const NodalBasis& basis, const Eigen::Vector3d& x0,
                 Scratch& sc, double* acc);

}  // namespace capflow::stokes
