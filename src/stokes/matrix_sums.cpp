#include "stokes/matrix_sums.h"

#include <algorithm>
#include <cmath>

#include "spectral/target_clones.h"
#include "stokes/lagrange_line.h"

namespace capflow::stokes {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using namespace detail;  // NOLINT: the shared stage-2 pieces (lagrange_line.h)

namespace {

// One line: G[c nb + j] = sum over the line's points of K_c L_j(along), total[c] += sum K_c.
// The points in chunks of up to kChunk blocks: their bases and kernel values stay on the stack,
// and each G entry gets one chunk's products summed in a register (a load and a store per
// kChunk multiply-adds instead of per one).
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void matrix_line(int nb, const LagrangeLine& ln, const NodalBasis& nbas, double sg,
                 const double* x0, double* G, double* total) {
  constexpr int kChunk = 4;
  double dA[3 * kMaxNb];
  along_derivative(nb, ln.A, nbas.diff, dA);
  vl g[6][kMaxNb];
  for (vl* gc : g)
    for (int j = 0; j < nb; ++j) gc[j] = kZero;
  vl tot[6];
  for (vl& v : tot) v = kZero;
  for (int c0 = 0; c0 < ln.m; c0 += kChunk * kW) {
    vl L[kChunk][kMaxNb], k[kChunk][6];
    const int blocks = std::min(kChunk, (ln.m - c0 + kW - 1) / kW);
    for (int b = 0; b < blocks; ++b) {
      vl wq, pad, X[3], Ac[3], Al[3], n[3];
      lagrange_block<false, true, true>(nb, ln, dA, nbas, c0 + b * kW, wq, pad, X, nullptr, Ac, Al,
                                        L[b]);
      weighted_normal(Ac, Al, wq, sg, n);
      const vl rx = X[0] - x0[0], ry = X[1] - x0[1], rz = X[2] - x0[2];
      vl ir = rx * rx + ry * ry + rz * rz + pad;
      inv_sqrt(ir);
      const vl ir2 = ir * ir;
      const vl a = -6.0 * (rx * n[0] + ry * n[1] + rz * n[2]) * (ir2 * ir2 * ir);
      const vl ax = a * rx, ay = a * ry;
      k[b][0] = ax * rx;
      k[b][1] = ay * ry;
      k[b][2] = a * rz * rz;
      k[b][3] = ax * ry;
      k[b][4] = ax * rz;
      k[b][5] = ay * rz;
      for (int c = 0; c < 6; ++c) tot[c] += k[b][c];
    }
    for (int c = 0; c < 6; ++c)
      for (int j = 0; j < nb; ++j) {
        vl s = k[0][c] * L[0][j];
        for (int b = 1; b < blocks; ++b) s += k[b][c] * L[b][j];
        g[c][j] += s;
      }
  }
  for (int c = 0; c < 6; ++c)
    for (int j = 0; j < nb; ++j) G[c * nb + j] = hsum(g[c][j]);
  for (int c = 0; c < 6; ++c) total[c] += hsum(tot[c]);
}

// Er (nb x w, row-major) += across G^T (first: = instead of +=): row a gets across[a] times G
// (w = 6 nb entries).
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void add_outer(int nb, int w, const double* across, const double* G, double* Er, bool first) {
  for (int a = 0; a < nb; ++a) {
    const double s = across[a];
    double* row = Er + static_cast<long>(a) * w;
    if (first) {
#pragma omp simd
      for (int q = 0; q < w; ++q) row[q] = s * G[q];
    } else {
#pragma omp simd
      for (int q = 0; q < w; ++q) row[q] += s * G[q];
    }
  }
}

}  // namespace

void line_matrix(int nb, const LineRule& R, const NodalBasis& basis, double sign,
                 const Vector3d& x0, Scratch& sc, MatrixWorkspace& ws, MatrixXd& E, double* total) {
  across_lines(nb, 3, R, sc);
  const int nl = R.nl(), n0 = R.n0, w = 6 * nb;
  // Per line the kernel sums against the bases along it (G, c nb + j), times the bases across
  // (rank-one updates): constant-s lines (across s = node index a, along t = b) into
  // Es(a, c nb + b), constant-t lines (across t = b, along s = a) into Et(b, c nb + a).
  RowMat &Es = ws.Es, &Et = ws.Et;
  Es.resize(nb, w);
  Et.resize(nb, w);
  bool first_s = true, first_t = true;  // nothing in Es / Et yet
  double G[6 * kMaxNb];
  for (int l = 0; l < nl; ++l) {
    const int m = R.start[l + 1] - R.start[l];
    if (m == 0) continue;
    const double sg = l < n0 ? sign : -sign;  // as line_sum: the tangents swap roles
    const LagrangeLine ln{sc.A.row(l).data(), sc.B.row(l).data(), R.base[l],       R.scale[l],
                          R.line_off(l),      R.wscale[l],        R.line_wedge(l), m};
    matrix_line(nb, ln, basis, sg, x0.data(), G, total);
    bool& first = l < n0 ? first_s : first_t;
    add_outer(nb, w, R.Lc.col(l).data(), G, l < n0 ? Es.data() : Et.data(), first);
    first = false;
  }
  if (first_s) Es.setZero();
  if (first_t) Et.setZero();
  E.resize(nb * nb, 6);
  for (int c = 0; c < 6; ++c)
    for (int b = 0; b < nb; ++b)
      for (int a = 0; a < nb; ++a) E(a + nb * b, c) = Es(a, c * nb + b) + Et(b, c * nb + a);
}

void far_matrix(const FarData& F, int q0, const MatrixXd& I, const Vector3d& x0,
                MatrixWorkspace& ws, MatrixXd& E, double* total) {
  const int nq = F.nq, nqe = nq * nq, nb = static_cast<int>(I.cols());
  ws.k.resize(nqe, 6);
  const double* px = F.d.row(0).data() + q0;
  const double* py = F.d.row(1).data() + q0;
  const double* pz = F.d.row(2).data() + q0;
  const double* nx = F.d.row(6).data() + q0;
  const double* ny = F.d.row(7).data() + q0;
  const double* nz = F.d.row(8).data() + q0;
  double* k0 = ws.k.col(0).data();
  double* k1 = ws.k.col(1).data();
  double* k2 = ws.k.col(2).data();
  double* k3 = ws.k.col(3).data();
  double* k4 = ws.k.col(4).data();
  double* k5 = ws.k.col(5).data();
  const double X0 = x0[0], X1 = x0[1], X2 = x0[2];
  double t0 = 0, t1 = 0, t2 = 0, t3 = 0, t4 = 0, t5 = 0;
#pragma omp simd reduction(+ : t0, t1, t2, t3, t4, t5)
  for (int q = 0; q < nqe; ++q) {
    const double rx = px[q] - X0, ry = py[q] - X1, rz = pz[q] - X2;
    const double ir = 1.0 / std::sqrt(rx * rx + ry * ry + rz * rz);
    const double ir2 = ir * ir;
    const double a = -6.0 * (rx * nx[q] + ry * ny[q] + rz * nz[q]) * (ir2 * ir2 * ir);
    k0[q] = a * rx * rx;
    k1[q] = a * ry * ry;
    k2[q] = a * rz * rz;
    k3[q] = a * rx * ry;
    k4[q] = a * rx * rz;
    k5[q] = a * ry * rz;
    t0 += k0[q];
    t1 += k1[q];
    t2 += k2[q];
    t3 += k3[q];
    t4 += k4[q];
    t5 += k5[q];
  }
  total[0] += t0;
  total[1] += t1;
  total[2] += t2;
  total[3] += t3;
  total[4] += t4;
  total[5] += t5;
  // Point (a, b) is q = a + nq b (far_data), node (i, j) is i + nb j: E_c = I^T K_c I. ws.k
  // viewed as nq x 6 nq is [K_0 .. K_5], so T = I^T [K_0 .. K_5] in one product; its blocks
  // stacked, [T_0; ..; T_5] I = [E_0; ..; E_5] in a second (two products instead of twelve).
  const Eigen::Map<const MatrixXd> Kcat(ws.k.data(), nq, 6 * nq);
  ws.t.noalias() = I.transpose() * Kcat;
  ws.stack.resize(6 * nb, nq);
  for (int c = 0; c < 6; ++c) ws.stack.middleRows(c * nb, nb) = ws.t.middleCols(c * nq, nq);
  ws.e.noalias() = ws.stack * I;
  E.resize(nb * nb, 6);
  for (int c = 0; c < 6; ++c)
    Eigen::Map<MatrixXd>(E.col(c).data(), nb, nb) = ws.e.middleRows(c * nb, nb);
}

}  // namespace capflow::stokes
