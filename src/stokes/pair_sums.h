// capflow/stokes/pair_sums: what an operator call (stokes/operator_call.h) does with the pairs of
// a target - the visitors of its per-target sums. The call decides, per pair, which rule applies
// (the target's own elements: their own rules; the others: stokes/pair_rule.h) and prepares a near
// rule; the visitor sums it:
//   VectorSums<M>   the kernel sums of a result vector (SL[f], DL[u], INT S.n, INT T.n) at the
//                   target: the single layer on Chebyshev data (and on the shared own lines), or
//                   J f interpolated; the others on the nodal data
//   MatrixAssembly  the assembled double layer: each pair's kernel sums added to the target's row
//                   block by the node expansion, their total subtracted at the target's column
// Each visitor is per thread and per call; begin() starts a target, finish() stores it. own() and
// near() return the single layer's counted flops (OperatorStats::flops), 0 for the others.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <vector>

#include "stokes/boundary_integral.h"
#include "stokes/far_field.h"
#include "stokes/kernel_mode.h"
#include "stokes/line_rule.h"
#include "stokes/line_sums.h"
#include "stokes/matrix_sums.h"
#include "stokes/own_lines.h"
#include "stokes/own_rules.h"

namespace capflow::stokes {

// The single layer's counted flops: stage 1 of `lines` lines, stage 2 and the kernel at
// `points` points.
inline double single_flops(int nb, double lines, double points) {
  const auto pad8 = [](int n) { return (n + 7) & ~7; };
  return lines * (2.0 * nb * (pad8(6 * nb) + pad8(3 * nb)) + 3.0 * nb) +
         points * (28.0 * nb + 36.0);
}
inline double single_rule_flops(int nb, const LineRule& r) {
  return single_flops(nb, r.nl(), r.np());
}

// What a call's visitors read (fixed for the call).
struct PairSumData {
  int nb = 0;
  int K = 0;  // rows of an element's loaded data: 3 (x) or 6 (x and the density)
  NodalBasis basis;
  const OwnRules* own = nullptr;
  const Eigen::Matrix3Xd* x = nullptr;
  const Eigen::Matrix3Xd* density = nullptr;   // the summed density (J f when interpolated)
  const std::vector<ChebElement>* cheb = nullptr;  // single layer: Chebyshev data, else null
  const OwnLines* own_lines = nullptr;         // single layer: the shared own lines, else null
  bool jf = false;                             // single layer with J f interpolated
  const FarBasis* far_basis = nullptr;         // the far tiers' rules (3)
};

template <Mode M>
class VectorSums {
 public:
  static constexpr int kRows = M == Mode::DoubleNormal ? 9 : 3;

  VectorSums(const PairSumData& d, Scratch& sc, Eigen::MatrixXd& out) : d_(d), sc_(sc), out_(out) {}

  // Target k at x0 (u0: the density there, the double layer's -u(x0) term; else unused).
  void begin(int /*k*/, const Eigen::Vector3d& x0, const Eigen::Vector3d& u0) {
    x0_ = x0;
    u0_ = u0;
    std::fill(acc_, acc_ + 9, 0.0);
  }

  // Own element e of the target (its node loc, the own rule r in symmetry sym).
  double own(int e, int loc, const LineRule& r, int sym) {
    const int nb = d_.nb;
    if (d_.own_lines) {
      sc_.rows.resize(r.nl());
      for (int l = 0; l < r.nl(); ++l)
        sc_.rows[l] =
            d_.own_lines->rows(e, OwnRules::element_line(r, l, sym), loc % nb, loc / nb);
      single_rows_sum(nb, r, sc_.rows.data(), x0_, acc_);
      return single_flops(nb, 0, r.np());
    }
    if (d_.cheb)
      load_chebyshev(nb, d_.K, (*d_.cheb)[e], sym, sc_);
    else
      load_element(nb, d_.K, *d_.x, d_.density, e * nb * nb, d_.own->permutation(sym), sc_);
    if (d_.jf)
      line_sum_jf(nb, r, d_.basis, x0_, sc_, acc_);
    else
      line_sum<M>(nb, d_.K, r, d_.basis, OwnRules::sign(sym), x0_, u0_, sc_, acc_);
    return M == Mode::Single ? single_rule_flops(nb, r) : 0.0;
  }

  // Element e by the near rule in sc.near.
  double near(int e) {
    const int nb = d_.nb;
    if (d_.cheb) {
      single_sum(nb, sc_.near, (*d_.cheb)[e], x0_, sc_, acc_);
    } else {
      load_element(nb, d_.K, *d_.x, d_.density, e * nb * nb, nullptr, sc_);
      if (d_.jf)
        line_sum_jf(nb, sc_.near, d_.basis, x0_, sc_, acc_);
      else
        line_sum<M>(nb, d_.K, sc_.near, d_.basis, 1.0, x0_, u0_, sc_, acc_);
    }
    return M == Mode::Single ? single_rule_flops(nb, sc_.near) : 0.0;
  }

  // Element e by the far data fd (its Gauss points e nq^2 .. (e + 1) nq^2 - 1).
  void far(const FarData& fd, int e, int /*tier*/) {
    const int nqe = fd.nq * fd.nq;
    far_sum<M>(fd, e * nqe, (e + 1) * nqe, x0_, u0_, acc_);
  }

  void finish(int k, int /*node*/) {
    for (int r = 0; r < kRows; ++r) out_(r, k) = acc_[r];
  }

 private:
  const PairSumData& d_;
  Scratch& sc_;
  Eigen::MatrixXd& out_;
  Eigen::Vector3d x0_, u0_;
  double acc_[9];
};

class MatrixAssembly {
 public:
  // matrix: 3 targets x 3 columns (zeroed); expansion: the columns of the nodes (null: a node
  // is its own column).
  MatrixAssembly(const PairSumData& d, Scratch& sc, MatrixWorkspace& mw, RowMat& matrix,
                 const NodeExpansion* expansion)
      : d_(d), sc_(sc), mw_(mw), matrix_(matrix), expansion_(expansion) {}

  void begin(int k, const Eigen::Vector3d& x0, const Eigen::Vector3d& /*u0*/) {
    k_ = k;
    x0_ = x0;
    std::fill(total_, total_ + 6, 0.0);
  }

  double own(int e, int /*loc*/, const LineRule& r, int sym) {
    const int nb = d_.nb;
    const int* perm = d_.own->permutation(sym);
    load_element(nb, d_.K, *d_.x, d_.density, e * nb * nb, perm, sc_);
    line_matrix(nb, r, d_.basis, OwnRules::sign(sym), x0_, sc_, mw_, mw_.E, total_);
    scatter(mw_.E, e * nb * nb, perm);
    return 0.0;
  }

  double near(int e) {
    const int nb = d_.nb;
    load_element(nb, d_.K, *d_.x, d_.density, e * nb * nb, nullptr, sc_);
    line_matrix(nb, sc_.near, d_.basis, 1.0, x0_, sc_, mw_, mw_.E, total_);
    scatter(mw_.E, e * nb * nb, nullptr);
    return 0.0;
  }

  void far(const FarData& fd, int e, int tier) {
    const int nqe = fd.nq * fd.nq;
    far_matrix(fd, e * nqe, d_.far_basis[tier].I, x0_, mw_, mw_.E, total_);
    scatter(mw_.E, e * d_.nb * d_.nb, nullptr);
  }

  // The kernel's sum (the -u(x0) term) at the target's own column.
  void finish(int /*k*/, int node) { place(node, total_, -1.0); }

 private:
  static double sym3(const double* s, int i, int j) {
    static constexpr int idx[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    return s[idx[i][j]];
  }
  // The symmetric 3x3 s (6 entries) times factor at node's column, in the target's rows.
  void place(int node, const double* s, double factor) {
    const int col = expansion_ ? expansion_->column[node] : node;
    for (int j = 0; j < 3; ++j) {
      const double sg = factor * (expansion_ ? expansion_->sign[node][j] : 1.0);
      for (int i = 0; i < 3; ++i) matrix_(3 * k_ + i, 3 * col + j) += sg * sym3(s, i, j);
    }
  }
  // An element's kernel sums E (node n in the rule's orientation: perm) at its nodes.
  void scatter(const Eigen::MatrixXd& E, int base, const int* perm) {
    double s[6];
    for (int n = 0; n < d_.nb * d_.nb; ++n) {
      for (int c = 0; c < 6; ++c) s[c] = E(n, c);
      place(base + (perm ? perm[n] : n), s, 1.0);
    }
  }

  const PairSumData& d_;
  Scratch& sc_;
  MatrixWorkspace& mw_;
  RowMat& matrix_;
  const NodeExpansion* expansion_;
  Eigen::Vector3d x0_;
  double total_[6];
  int k_ = 0;
};

}  // namespace capflow::stokes
