#include "stokes/matrix_sums.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "spectral/target_clones.h"
#include "stokes/lagrange_line.h"

namespace capflow::stokes {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using namespace detail;  // NOLINT: the shared stage-2 pieces (lagrange_line.h)

namespace {

// The six entries (xx, yy, zz, xy, xz, yz) of the double-layer kernel -6 (r.n) r r^T / r^5 at a
// point, n the weighted normal w J n and ir = 1 / |r|: for a vector of points (vec<W>) in the
// special rules and for one Gauss point (double) in the far tiers.
template <class T>
[[gnu::always_inline]] inline void kernel_entries(T rx, T ry, T rz, T nx, T ny, T nz, T ir, T& kxx,
                                                  T& kyy, T& kzz, T& kxy, T& kxz, T& kyz) {
  const T ir2 = ir * ir;
  const T a = -6.0 * (rx * nx + ry * ny + rz * nz) * (ir2 * ir2 * ir);
  const T ax = a * rx, ay = a * ry;
  kxx = ax * rx;
  kyy = ay * ry;
  kzz = a * rz * rz;
  kxy = ax * ry;
  kxz = ax * rz;
  kyz = ay * rz;
}

// NP points of a line group (one per lane and line): their Lagrange bases along the lines into
// L[q] and the 6 entries of the kernel (times w J) into k[q], added to tot. The points go side by
// side (independent product chains for the bases, one load of the nodal data for all).
template <int NP, int W>
[[gnu::always_inline]] inline void kernel_points(int nb, const vec<W>* ov, const vec<W>* wq,
                                                 double sg, const NodalBasis& nbas, const vec<W>* A,
                                                 const vec<W>* B, const vec<W>* dA,
                                                 const double* x0, vec<W> (*L)[kMaxNb],
                                                 vec<W> (*k)[6], vec<W>* tot) {
  using vl = vec<W>;
  const vl kZero = vec<W>{}, kOne = vec<W>{} + 1.0;
  vl pre[NP][kMaxNb];  // c_j prod_{k < j} (o - x_k)
  vl P[NP];
  for (int q = 0; q < NP; ++q) P[q] = kOne;
  for (int j = 0; j < nb; ++j)
    for (int q = 0; q < NP; ++q) {
      pre[q][j] = nbas.weights[j] * P[q];
      P[q] = P[q] * (ov[q] - nbas.nodes[j]);
    }
  vl X[NP][3], Ac[NP][3], Al[NP][3];
  for (int q = 0; q < NP; ++q) {
    P[q] = kOne;  // prod_{k > j} (o - x_k)
    for (int c = 0; c < 3; ++c) X[q][c] = Ac[q][c] = Al[q][c] = kZero;
  }
  for (int j = nb - 1; j >= 0; --j) {
    vl Lj[NP];
    for (int q = 0; q < NP; ++q) {
      Lj[q] = pre[q][j] * P[q];
      L[q][j] = Lj[q];
      P[q] = P[q] * (ov[q] - nbas.nodes[j]);
    }
    for (int c = 0; c < 3; ++c) {
      const vl a = A[c * nb + j], b = B[c * nb + j], e = dA[c * nb + j];
      for (int q = 0; q < NP; ++q) {
        X[q][c] += a * Lj[q];
        Ac[q][c] += b * Lj[q];
        Al[q][c] += e * Lj[q];
      }
    }
  }
  for (int q = 0; q < NP; ++q) {
    vl nv[3];
    weighted_normal<W>(Ac[q], Al[q], wq[q], sg, nv);
    const vl rx = X[q][0] - x0[0], ry = X[q][1] - x0[1], rz = X[q][2] - x0[2];
    vl ir = rx * rx + ry * ry + rz * rz;
    inv_sqrt<W>(ir);
    kernel_entries(rx, ry, rz, nv[0], nv[1], nv[2], ir, k[q][0], k[q][1], k[q][2], k[q][3], k[q][4],
                   k[q][5]);
    for (int c = 0; c < 6; ++c) tot[c] += k[q][c];
  }
}

// Up to W lines of one edge point set (lines l0 .. l0 + n - 1: the same points along, at
// different ray fractions), one line per lane: Gt(c nb + j, l) = sum over line l's points of
// K_c L_j(along), tot[c] += K_c. The lanes are one point index of every line, so a line's sums
// stay in its lane (no horizontal sums per line) and the lines of one edge fill the lanes evenly.
// The points in chunks of kChunk: their bases and kernel values stay on the stack, and each Gt
// entry gets one chunk's products summed in a register. Lanes past n repeat line l0 + n - 1 with
// weight 0; Gt gets W columns from l0 on (the columns past n belong to the next group or lie past
// the rule).
template <int W>
[[gnu::always_inline]] inline void matrix_part(int nb, const LineRule& R, int l0, int n,
                                               const double* D, long ldD, const NodalBasis& nbas,
                                               double sg, const double* x0, double* Gt, long ldG,
                                               vec<W>* tot) {
  using vl = vec<W>;
  const vl kZero = vec<W>{};
  constexpr int kChunk = 4;
  constexpr int kPair = W == 8 ? 2 : 1;  // points side by side (two spill the 16 AVX2 registers)
  vl A[3 * kMaxNb + 4], B[3 * kMaxNb + 4], dA[3 * kMaxNb];  // + 4: stage 1 fills whole fours
  vl base, scale, wscale, Lc[kMaxNb], dLc[kMaxNb];
  for (int q = 0; q < W; ++q) {
    const int l = l0 + std::min(q, n - 1);
    for (int i = 0; i < nb; ++i) {
      Lc[i][q] = R.Lc(i, l);
      dLc[i][q] = R.dLc(i, l);
    }
    base[q] = R.base[l];
    scale[q] = R.scale[l];
    wscale[q] = q < n ? R.wscale[l] : 0.0;
  }
  // stage 1 in the lanes: the element data D (row i: across node i) interpolated across to each
  // line, A = the position at the along nodes, B = its derivative across; four columns at a time
  // (eight independent sums; D has padding columns past 3 nb)
  for (int k0 = 0; k0 < 3 * nb; k0 += 4) {
    vl a[4] = {kZero, kZero, kZero, kZero}, b[4] = {kZero, kZero, kZero, kZero};
    for (int i = 0; i < nb; ++i) {
      const double* row = D + i * ldD + k0;
      for (int j = 0; j < 4; ++j) {
        a[j] += Lc[i] * row[j];
        b[j] += dLc[i] * row[j];
      }
    }
    for (int j = 0; j < 4; ++j) {
      A[k0 + j] = a[j];
      B[k0 + j] = b[j];
    }
  }
  // the derivative along each line at its along nodes (exact for the line's polynomial), four
  // nodes at a time
  for (int c = 0; c < 3; ++c)
    for (int i0 = 0; i0 < nb; i0 += 4) {
      int col[4];
      for (int j = 0; j < 4; ++j) col[j] = std::min(i0 + j, nb - 1);
      vl d[4] = {kZero, kZero, kZero, kZero};
      for (int k = 0; k < nb; ++k) {
        const vl a = A[c * nb + k];
        for (int j = 0; j < 4; ++j) d[j] += nbas.diff[col[j] + k * nb] * a;
      }
      for (int j = 0; j < 4 && i0 + j < nb; ++j) dA[c * nb + i0 + j] = d[j];
    }
  const double* off = R.line_off(l0);
  const double* wedge = R.line_wedge(l0);
  const int m = R.start[l0 + 1] - R.start[l0];
  vl g[6][kMaxNb];
  for (vl* gc : g)
    for (int j = 0; j < nb; ++j) gc[j] = kZero;
  for (int p0 = 0; p0 < m; p0 += kChunk) {
    vl L[kChunk][kMaxNb], k[kChunk][6];
    const int points = std::min(kChunk, m - p0);
    int q = 0;
    for (; kPair == 2 && q + 1 < points; q += 2) {
      const vl ov[2] = {base + scale * off[p0 + q], base + scale * off[p0 + q + 1]};
      const vl wq[2] = {wscale * wedge[p0 + q], wscale * wedge[p0 + q + 1]};
      kernel_points<2, W>(nb, ov, wq, sg, nbas, A, B, dA, x0, L + q, k + q, tot);
    }
    for (; q < points; ++q) {
      const vl ov[1] = {base + scale * off[p0 + q]}, wq[1] = {wscale * wedge[p0 + q]};
      kernel_points<1, W>(nb, ov, wq, sg, nbas, A, B, dA, x0, L + q, k + q, tot);
    }
    if (points == kChunk) {
      // a whole chunk: the kernel values stay in registers, each basis is loaded once
      for (int j = 0; j < nb; ++j) {
        vl Lb[kChunk];
        for (int b = 0; b < kChunk; ++b) Lb[b] = L[b][j];
        for (int c = 0; c < 6; ++c) {
          vl s = k[0][c] * Lb[0];
          for (int b = 1; b < kChunk; ++b) s += k[b][c] * Lb[b];
          g[c][j] += s;
        }
      }
    } else {
      for (int c = 0; c < 6; ++c)
        for (int j = 0; j < nb; ++j) {
          vl s = k[0][c] * L[0][j];
          for (int b = 1; b < points; ++b) s += k[b][c] * L[b][j];
          g[c][j] += s;
        }
    }
  }
  for (int c = 0; c < 6; ++c)
    for (int j = 0; j < nb; ++j) std::memcpy(Gt + (c * nb + j) * ldG + l0, &g[c][j], sizeof(vl));
}

// Up to kBlock lines of one edge point set (lines l0 .. l0 + n - 1), in parts of W lines
// (matrix_part), total[c] += sum K_c over all their points, summed over the kBlock lanes in one
// order for every width.
template <int W>
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void matrix_lines(int nb, const LineRule& R, int l0, int n, const double* D, long ldD,
                  const NodalBasis& nbas, double sg, const double* x0, double* Gt, long ldG,
                  double* total) {
  vec<W> tot[6][kParts<W>];
  for (auto& c : tot)
    for (vec<W>& v : c) v = vec<W>{};
  for (int h = 0; h < kParts<W> && h * W < n; ++h) {
    vec<W> t[6];
    for (vec<W>& v : t) v = vec<W>{};
    matrix_part<W>(nb, R, l0 + h * W, std::min(W, n - h * W), D, ldD, nbas, sg, x0, Gt, ldG, t);
    for (int c = 0; c < 6; ++c) tot[c][h] = t[c];
  }
  for (int c = 0; c < 6; ++c) total[c] += hsum<W>(tot[c]);
}

}  // namespace

void line_matrix(int nb, const LineRule& R, const NodalBasis& basis, double sign,
                 const Vector3d& x0, Scratch& sc, MatrixWorkspace& ws, MatrixXd& E, double* total) {
  const int nl = R.nl(), n0 = R.n0, n1 = nl - n0;
  // Per line the kernel sums against the bases along it (Gt(c nb + j, l)), in groups of up to
  // kBlock lines of one edge point set (they never straddle n0: an edge's lines share an
  // orientation); then the bases across times them in two products: constant-s lines (across
  // s = node index a, along t = b) into Es(a, c nb + b), constant-t lines (across t = b, along
  // s = a) into Et(b, c nb + a). A group writes up to kBlock columns, so Gt holds kBlock more than
  // the lines.
  RowMat& Gt = ws.Gt;
  if (Gt.rows() != 6 * nb || Gt.cols() < nl + kBlock) Gt.resize(6 * nb, nl + kBlock);
  at_simd_width([&](auto w) {
    for (int l = 0; l < nl;) {
      int n = 1;
      while (n < kBlock && l + n < nl && R.set[l + n] == R.set[l]) ++n;
      const double sg = l < n0 ? sign : -sign;   // as line_sum: the tangents swap roles
      const RowMat& D = l < n0 ? sc.D0 : sc.D1;  // the element data with the across index as row
      matrix_lines<decltype(w)::value>(nb, R, l, n, D.data(), D.cols(), basis, sg, x0.data(),
                                       Gt.data(), Gt.cols(), total);
      l += n;
    }
  });
  RowMat &Es = ws.Es, &Et = ws.Et;
  if (n0 > 0)
    Es.noalias() = R.Lc.leftCols(n0) * Gt.leftCols(n0).transpose();
  else
    Es.setZero(nb, 6 * nb);
  if (n1 > 0)
    Et.noalias() = R.Lc.middleCols(n0, n1) * Gt.middleCols(n0, n1).transpose();
  else
    Et.setZero(nb, 6 * nb);
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
    kernel_entries(rx, ry, rz, nx[q], ny[q], nz[q], ir, k0[q], k1[q], k2[q], k3[q], k4[q], k5[q]);
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
