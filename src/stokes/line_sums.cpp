#include "stokes/line_sums.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "spectral/spectral.h"
#include "spectral/target_clones.h"
#include "stokes/kernel_point.h"
#include "stokes/lagrange_line.h"

namespace capflow::stokes {

using namespace detail;  // NOLINT: the shared stage-2 pieces (lagrange_line.h)

using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {
// Columns of the stage-1 operands, rounded up to whole blocks of 8 (two v4d): stage1 reads and
// writes whole blocks, so D, A and B carry up to 7 padding columns (their values are unused).
constexpr int pad8(int n) {
  return (n + 7) & ~7;
}
}  // namespace

// Element data (x and, if K == 6, the density) in the orientation given by perm (canonical
// (a + nb b) -> local node within the element).
void load_element(int nb, int K, const Matrix3Xd& x, const Matrix3Xd* dens, int base,
                  const int* perm, Scratch& sc) {
  for (int b = 0; b < nb; ++b)
    for (int a = 0; a < nb; ++a) {
      const int src = base + (perm ? perm[a + nb * b] : a + nb * b);
      for (int c = 0; c < 3; ++c) {
        sc.D0(a, c * nb + b) = x(c, src);
        sc.D1(b, c * nb + a) = x(c, src);
      }
      if (K == 6)
        for (int c = 0; c < 3; ++c) {
          sc.D0(a, (3 + c) * nb + b) = (*dens)(c, src);
          sc.D1(b, (3 + c) * nb + a) = (*dens)(c, src);
        }
    }
}

void chebyshev_element(int nb, int c0, int c1, const MatrixXd& C, const Matrix3Xd& x,
                       const Matrix3Xd* dens, int base, ChebElement& ce) {
  const int kp = pad8(6 * nb);
  if (ce.cs.rows() != nb || ce.cs.cols() != kp) {
    ce.cs.setZero(nb, kp);
    ce.ct.setZero(nb, kp);
  }
  for (int c = c0; c < c1; ++c) {
    const Matrix3Xd& v = c < 3 ? x : *dens;
    const int r = c % 3;
    for (int i = 0; i < nb; ++i)  // row i of cs: the coefficients in t at s_i; of ct: in s at t_i
      for (int k = 0; k < nb; ++k) {
        double st = 0, ss = 0;
        for (int j = 0; j < nb; ++j) {
          st += C(k, j) * v(r, base + i + nb * j);
          ss += C(k, j) * v(r, base + j + nb * i);
        }
        ce.cs(i, c * nb + k) = st;
        ce.ct(i, c * nb + k) = ss;
      }
  }
}

void load_chebyshev(int nb, int K, const ChebElement& ce, int sym, Scratch& sc) {
  const bool fs = sym & 1, ft = sym & 2, sw = sym & 4;
  // D0 row a (canonical s-node) holds the coefficients along canonical t, D1 row b those along
  // canonical s. Without a swap: canonical s, t = actual s, t (flipped as fs, ft); with one:
  // canonical s = actual t, canonical t = actual s. A flipped along coordinate turns c_k into
  // (-1)^k c_k (T_k(-t) = (-1)^k T_k(t); the nodes are symmetric).
  const RowMat& r0 = sw ? ce.ct : ce.cs;  // rows by the actual node of canonical s
  const RowMat& r1 = sw ? ce.cs : ce.ct;
  const bool flip_row0 = sw ? ft : fs, flip_along0 = sw ? fs : ft;
  const bool flip_row1 = sw ? fs : ft, flip_along1 = sw ? ft : fs;
  for (int a = 0; a < nb; ++a) {
    const double* s0 = r0.row(flip_row0 ? nb - 1 - a : a).data();
    const double* s1 = r1.row(flip_row1 ? nb - 1 - a : a).data();
    double* d0 = sc.D0.row(a).data();
    double* d1 = sc.D1.row(a).data();
    for (int c = 0; c < K; ++c)
      for (int k = 0; k < nb; ++k) {
        const int q = c * nb + k;
        d0[q] = (flip_along0 && (k & 1)) ? -s0[q] : s0[q];
        d1[q] = (flip_along1 && (k & 1)) ? -s1[q] : s1[q];
      }
  }
}

namespace {

// Single layer, one line of a line rule: stage 2 (values along the line from the stage-1 rows
// A (x, f: 6 nb Chebyshev coefficients in the along coordinate) and B (d/d(across) x: 3 nb))
// and the kernel sum, added to out[0..2]. The line's m points o_j = base + scale off[j] (along
// coordinate) with weights w_j = wscale wedge[j] (LineRule). Vectors of W points with the 12
// interpolated values in registers (GCC vector extension): T_k by T_{k+1} = 2 o T_k - T_{k-1}, T_k'
// = k U_{k-1} with U likewise. Compiled three times (x86-64-v4 with AVX-512, x86-64-v3 with
// AVX2/FMA, and the default), chosen at load time; at_simd_width calls the instance of the CPU's
// width W (lagrange_line.h).
typedef double v4d __attribute__((vector_size(32)));

// Stage 2 of the single layer at the points ov of a line: Values, the position and density
// V = (x, f) from the Chebyshev coefficients A (6 nb), and Tangents, D = (x_across, x_along) from
// B (3 nb) and kx = k A (the along derivative's U weights), by T_{k+1} = 2 o T_k - T_{k-1} and
// U likewise. Each sum runs over k in order, so one pass or two give the same bits.
template <int W, bool Values, bool Tangents>
[[gnu::always_inline]] inline void chebyshev_sums(int nb, const double* A, const double* B,
                                                  const double* kx, vec<W> ov, vec<W>* V,
                                                  vec<W>* D) {
  using vl = vec<W>;
  const vl zero = vec<W>{}, one = vec<W>{} + 1.0;
  const vl o2 = ov + ov;
  vl X0, X1, X2, F0, F1, F2, A0, A1, A2, O0, O1, O2;
  if constexpr (Values) {
    X0 = A[0] * one, X1 = A[nb] * one, X2 = A[2 * nb] * one;
    F0 = A[3 * nb] * one, F1 = A[4 * nb] * one, F2 = A[5 * nb] * one;
  }
  if constexpr (Tangents) {
    A0 = B[0] * one, A1 = B[nb] * one, A2 = B[2 * nb] * one;
    O0 = zero, O1 = zero, O2 = zero;
  }
  vl Tm = one, T = ov, Um = zero, U = one;  // T_{k-1}, T_k, U_{k-2}, U_{k-1} at k = 1
  for (int k = 1; k < nb; ++k) {
    if constexpr (Values) {
      X0 += A[k] * T;
      X1 += A[nb + k] * T;
      X2 += A[2 * nb + k] * T;
      F0 += A[3 * nb + k] * T;
      F1 += A[4 * nb + k] * T;
      F2 += A[5 * nb + k] * T;
    }
    if constexpr (Tangents) {
      A0 += B[k] * T;
      A1 += B[nb + k] * T;
      A2 += B[2 * nb + k] * T;
      O0 += kx[k] * U;
      O1 += kx[nb + k] * U;
      O2 += kx[2 * nb + k] * U;
      const vl Un = o2 * U - Um;
      Um = U;
      U = Un;
    }
    const vl Tn = o2 * T - Tm;
    Tm = T;
    T = Tn;
  }
  if constexpr (Values) {
    V[0] = X0, V[1] = X1, V[2] = X2, V[3] = F0, V[4] = F1, V[5] = F2;
  }
  if constexpr (Tangents) {
    D[0] = A0, D[1] = A1, D[2] = A2, D[3] = O0, D[4] = O1, D[5] = O2;
  }
}

template <int W>
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void single_line(int nb, int m, const double* A, const double* B, double base, double scale,
                 const double* off, double wscale, const double* wedge, const double* x0,
                 double* out) {
  using vl = vec<W>;
  double kx[3 * kMaxNb];  // k c_k of the position's coefficients (the derivative's U weights)
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < nb; ++k) kx[c * nb + k] = k * A[c * nb + k];
  const vl zero = vec<W>{}, one = vec<W>{} + 1.0;
  const vl x00 = x0[0] * one, x01 = x0[1] * one, x02 = x0[2] * one;
  vl s0[kParts<W>], s1[kParts<W>], s2[kParts<W>];
  for (int h = 0; h < kParts<W>; ++h) s0[h] = s1[h] = s2[h] = zero;
  for (int p0 = 0; p0 < m; p0 += W) {
    const int h = part_of<W>(p0);
    vl ov, wq, pad;
    for (int q = 0; q < W; ++q) {
      const bool in = p0 + q < m;
      ov[q] = in ? base + scale * off[p0 + q] : 0.0;
      wq[q] = in ? wscale * wedge[p0 + q] : 0.0;
      pad[q] = in ? 0.0 : 1.0;
    }
    // the 12 sums in one pass with 32 vector registers (AVX-512), in two with 16
    vl V[6], D[6];
    if constexpr (W == kBlock) {
      chebyshev_sums<W, true, true>(nb, A, B, kx, ov, V, D);
    } else {
      chebyshev_sums<W, true, false>(nb, A, B, kx, ov, V, D);
      chebyshev_sums<W, false, true>(nb, A, B, kx, ov, V, D);
    }
    const vl &X0 = V[0], &X1 = V[1], &X2 = V[2], &F0 = V[3], &F1 = V[4], &F2 = V[5];
    const vl &A0 = D[0], &A1 = D[1], &A2 = D[2], &O0 = D[3], &O1 = D[4], &O2 = D[5];
    const vl nx = A1 * O2 - A2 * O1;
    const vl ny = A2 * O0 - A0 * O2;
    const vl nz = A0 * O1 - A1 * O0;
    const vl rx = X0 - x00, ry = X1 - x01, rz = X2 - x02;
    const vl r2 = rx * rx + ry * ry + rz * rz + pad;
    const vl n2 = nx * nx + ny * ny + nz * nz;
    vl ir, nn;
    for (int q = 0; q < W; ++q) {
      ir[q] = 1.0 / std::sqrt(r2[q]);
      nn[q] = std::sqrt(n2[q]);
    }
    const vl aa = wq * nn * ir;
    const vl bb = aa * ir * ir * (rx * F0 + ry * F1 + rz * F2);
    s0[h] += aa * F0 + bb * rx;
    s1[h] += aa * F1 + bb * ry;
    s2[h] += aa * F2 + bb * rz;
  }
  out[0] += hsum<W>(s0);
  out[1] += hsum<W>(s1);
  out[2] += hsum<W>(s2);
}

}  // namespace

// Sizes a scratch's line buffers A, B (size_lines) and element data D0, D1 (size_scratch, padding
// zeroed) for nb nodes per direction and rules of up to `lines` lines, with padded columns (pad8).
// Buffers that are big enough are kept (size_scratch keeps loaded element data of the same nb).
void size_lines(Scratch& sc, int nb, int lines) {
  const int kp = pad8(6 * nb), k3 = pad8(3 * nb);
  if (sc.A.rows() < lines || sc.A.cols() != kp || sc.B.cols() != k3) {
    sc.A.resize(std::max<Eigen::Index>(lines, sc.A.rows()), kp);
    sc.B.resize(sc.A.rows(), k3);
  }
}
void size_scratch(Scratch& sc, int nb, int lines) {
  const int kp = pad8(6 * nb);
  if (sc.D0.rows() != nb || sc.D0.cols() != kp) {
    sc.D0.setZero(nb, kp);
    sc.D1.setZero(nb, kp);
  }
  size_lines(sc, nb, lines);
}

namespace {

// One register block of stage 1: columns k .. k+7 of A (and of B if WithB) for NL (1 or 2)
// lines with bases c[r], e[r] and outputs a[r], b[r]. Each sum runs over i in order.
template <int NL, bool WithB>
__attribute__((always_inline)) inline void stage1_block(int nb, int k, const double* const* c,
                                                        const double* const* e, const double* D,
                                                        long ldD, double* const* a,
                                                        double* const* b) {
  v4d p[NL][2], q[NL][2];
  for (int r = 0; r < NL; ++r) p[r][0] = p[r][1] = q[r][0] = q[r][1] = v4d{0, 0, 0, 0};
  for (int i = 0; i < nb; ++i) {
    v4d d0, d1;
    std::memcpy(&d0, D + i * ldD + k, sizeof d0);
    std::memcpy(&d1, D + i * ldD + k + 4, sizeof d1);
    for (int r = 0; r < NL; ++r) {
      p[r][0] += c[r][i] * d0;
      p[r][1] += c[r][i] * d1;
      if constexpr (WithB) {
        q[r][0] += e[r][i] * d0;
        q[r][1] += e[r][i] * d1;
      }
    }
  }
  for (int r = 0; r < NL; ++r) {
    std::memcpy(a[r] + k, &p[r][0], sizeof(v4d));
    std::memcpy(a[r] + k + 4, &p[r][1], sizeof(v4d));
    if constexpr (WithB) {
      std::memcpy(b[r] + k, &q[r][0], sizeof(v4d));
      std::memcpy(b[r] + k + 4, &q[r][1], sizeof(v4d));
    }
  }
}

// Stage 1 for NL (1 or 2) lines from line l: every block of columns, B only where it has them.
template <int NL>
__attribute__((always_inline)) inline void stage1_lines(int nb, int l, int kp, int k3,
                                                        const double* Lc, const double* dLc,
                                                        const double* D, long ldD, double* A,
                                                        long ldA, double* B, long ldB) {
  const double *c[NL], *e[NL];
  double *a[NL], *b[NL];
  for (int r = 0; r < NL; ++r) {
    c[r] = Lc + static_cast<long>(l + r) * nb;
    e[r] = dLc + static_cast<long>(l + r) * nb;
    a[r] = A + (l + r) * ldA;
    b[r] = B + (l + r) * ldB;
  }
  for (int k = 0; k < kp; k += 8) {
    if (k < k3)
      stage1_block<NL, true>(nb, k, c, e, D, ldD, a, b);
    else
      stage1_block<NL, false>(nb, k, c, e, D, ldD, a, b);
  }
}

// Stage 1 for nl lines: A(l, :) = sum_i Lc(i, l) D(i, 0:Kn), B(l, :) = sum_i dLc(i, l)
// D(i, 0:n3) (row-major D, A, B; Lc, dLc column l at + l nb). Register blocks of two lines x 8
// columns (the rows of D are read once per pair of lines and the sums stay in registers); D, A
// and B must hold pad8(Kn) / pad8(n3) columns. The sums run over i in order, as a plain loop
// would. Cloned like single_line.
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void stage1(int nb, int nl, int Kn, int n3, const double* Lc, const double* dLc, const double* D,
            long ldD, double* A, long ldA, double* B, long ldB) {
  const int kp = pad8(Kn), k3 = pad8(n3);
  int l = 0;
  for (; l + 1 < nl; l += 2) stage1_lines<2>(nb, l, kp, k3, Lc, dLc, D, ldD, A, ldA, B, ldB);
  if (l < nl) stage1_lines<1>(nb, l, kp, k3, Lc, dLc, D, ldD, A, ldA, B, ldB);
}

}  // namespace

namespace {

// The sums of a Lagrange-mode line: C components per part of a block, zeroed.
template <int W, int C>
struct LineSums {
  vec<W> s[C][kParts<W>];
  [[gnu::always_inline]] LineSums() {
    for (auto& c : s)
      for (vec<W>& v : c) v = vec<W>{};
  }
  [[gnu::always_inline]] void add_to(double* out) const {
    for (int c = 0; c < C; ++c) out[c] += hsum<W>(s[c]);
  }
};

// INT S.n dS over one line: out[0..2] += sum w (n / r + (r.n) r / r^3) (kernel_point.h).
template <int W>
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void normal_line(int nb, const LagrangeLine& ln, const NodalBasis& nbas, double sg,
                 const double* x0, double* out) {
  using vl = vec<W>;
  double dA[3 * kMaxNb];
  along_derivative(nb, ln.A, nbas.diff, dA);
  LineSums<W, 3> s;
  for (int p0 = 0; p0 < ln.m; p0 += W) {
    const int h = part_of<W>(p0);
    vl wq, pad, X[3], Ac[3], Al[3], n[3];
    lagrange_block<false, true, W>(nb, ln, dA, nbas, p0, wq, pad, X, nullptr, Ac, Al);
    weighted_normal<W>(Ac, Al, wq, sg, n);
    const vl rx = X[0] - x0[0], ry = X[1] - x0[1], rz = X[2] - x0[2];
    vl ir = rx * rx + ry * ry + rz * rz + pad;
    inv_sqrt<W>(ir);
    const vl b = (rx * n[0] + ry * n[1] + rz * n[2]) * ir * ir * ir;
    s.s[0][h] += ir * n[0] + b * rx;
    s.s[1][h] += ir * n[1] + b * ry;
    s.s[2][h] += ir * n[2] + b * rz;
  }
  s.add_to(out);
}

// The double layer over one line: out[0..2] += sum -6 (r.(u - u0)) (r.n) r / r^5.
template <int W>
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void double_line(int nb, const LagrangeLine& ln, const NodalBasis& nbas, double sg,
                 const double* x0, const double* u0, double* out) {
  using vl = vec<W>;
  double dA[3 * kMaxNb];
  along_derivative(nb, ln.A, nbas.diff, dA);
  LineSums<W, 3> s;
  for (int p0 = 0; p0 < ln.m; p0 += W) {
    const int h = part_of<W>(p0);
    vl wq, pad, X[3], F[3], Ac[3], Al[3], n[3];
    lagrange_block<true, true, W>(nb, ln, dA, nbas, p0, wq, pad, X, F, Ac, Al);
    weighted_normal<W>(Ac, Al, wq, sg, n);
    const vl rx = X[0] - x0[0], ry = X[1] - x0[1], rz = X[2] - x0[2];
    vl ir = rx * rx + ry * ry + rz * rz + pad;
    inv_sqrt<W>(ir);
    const vl rq = rx * (F[0] - u0[0]) + ry * (F[1] - u0[1]) + rz * (F[2] - u0[2]);
    const vl ir2 = ir * ir;
    const vl a = -6.0 * rq * (rx * n[0] + ry * n[1] + rz * n[2]) * (ir2 * ir2 * ir);
    s.s[0][h] += a * rx;
    s.s[1][h] += a * ry;
    s.s[2][h] += a * rz;
  }
  s.add_to(out);
}

// INT T.n dS over one line: out[0..8] (column-major 3 x 3) += sum -6 (r.n) r r^T / r^5.
template <int W>
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void double_normal_line(int nb, const LagrangeLine& ln, const NodalBasis& nbas, double sg,
                        const double* x0, double* out) {
  using vl = vec<W>;
  double dA[3 * kMaxNb];
  along_derivative(nb, ln.A, nbas.diff, dA);
  LineSums<W, 9> s;
  for (int p0 = 0; p0 < ln.m; p0 += W) {
    const int h = part_of<W>(p0);
    vl wq, pad, X[3], Ac[3], Al[3], n[3];
    lagrange_block<false, true, W>(nb, ln, dA, nbas, p0, wq, pad, X, nullptr, Ac, Al);
    weighted_normal<W>(Ac, Al, wq, sg, n);
    const vl r[3] = {X[0] - x0[0], X[1] - x0[1], X[2] - x0[2]};
    vl ir = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + pad;
    inv_sqrt<W>(ir);
    const vl ir2 = ir * ir;
    const vl a = -6.0 * (r[0] * n[0] + r[1] * n[1] + r[2] * n[2]) * (ir2 * ir2 * ir);
    for (int col = 0; col < 3; ++col) {
      const vl ac = a * r[col];
      for (int row = 0; row < 3; ++row) s.s[3 * col + row][h] += ac * r[row];
    }
  }
  s.add_to(out);
}

// The single layer with g = J f interpolated (A: x, g at the along nodes): out[0..2] += sum w
// (g / r + (r.g) r / r^3).
template <int W>
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void jf_line(int nb, const LagrangeLine& ln, const NodalBasis& nbas, const double* x0,
             double* out) {
  using vl = vec<W>;
  LineSums<W, 3> s;
  for (int p0 = 0; p0 < ln.m; p0 += W) {
    const int h = part_of<W>(p0);
    vl wq, pad, X[3], G[3];
    lagrange_block<true, false, W>(nb, ln, nullptr, nbas, p0, wq, pad, X, G, nullptr, nullptr);
    const vl rx = X[0] - x0[0], ry = X[1] - x0[1], rz = X[2] - x0[2];
    vl ir = rx * rx + ry * ry + rz * rz + pad;
    inv_sqrt<W>(ir);
    const vl a = wq * ir;
    const vl b = a * ir * ir * (rx * G[0] + ry * G[1] + rz * G[2]);
    s.s[0][h] += a * G[0] + b * rx;
    s.s[1][h] += a * G[1] + b * ry;
    s.s[2][h] += a * G[2] + b * rz;
  }
  s.add_to(out);
}

// Stage 2 of every line of rule R (stage 1 done: sc.A, sc.B), W points at a time.
template <Mode M, int W>
void lines_stage2(int nb, const LineRule& R, const NodalBasis& basis, double sign,
                  const Vector3d& x0, const Vector3d& u0, Scratch& sc, double* acc) {
  const int nl = R.nl(), n0 = R.n0;
  for (int l = 0; l < nl; ++l) {
    const int m = R.start[l + 1] - R.start[l];
    if (m == 0) continue;
    if constexpr (M == Mode::Single) {
      (void)sign;  // |n| does not depend on the orientation
      (void)u0;
      single_line<W>(nb, m, sc.A.row(l).data(), sc.B.row(l).data(), R.base[l], R.scale[l],
                     R.line_off(l), R.wscale[l], R.line_wedge(l), x0.data(), acc);
      continue;
    }
    // n = x_s x x_t: constant-s lines: x_s = d/d(across), x_t = d/d(along); constant-t lines:
    // swapped.
    const double sg = l < n0 ? sign : -sign;
    const LagrangeLine ln{sc.A.row(l).data(), sc.B.row(l).data(), R.base[l],       R.scale[l],
                          R.line_off(l),      R.wscale[l],        R.line_wedge(l), m};
    if constexpr (M == Mode::SingleNormal)
      normal_line<W>(nb, ln, basis, sg, x0.data(), acc);
    else if constexpr (M == Mode::Double)
      double_line<W>(nb, ln, basis, sg, x0.data(), u0.data(), acc);
    else if constexpr (M == Mode::DoubleNormal)
      double_normal_line<W>(nb, ln, basis, sg, x0.data(), acc);
  }
}

// The same for the single layer with J f interpolated (no tangents: sc.B is not read).
template <int W>
void jf_lines_stage2(int nb, const LineRule& R, const NodalBasis& basis, const Vector3d& x0,
                     Scratch& sc, double* acc) {
  for (int l = 0; l < R.nl(); ++l) {
    const int m = R.start[l + 1] - R.start[l];
    if (m == 0) continue;
    const LagrangeLine ln{sc.A.row(l).data(), nullptr,     R.base[l],       R.scale[l],
                          R.line_off(l),      R.wscale[l], R.line_wedge(l), m};
    jf_line<W>(nb, ln, basis, x0.data(), acc);
  }
}

}  // namespace

void across_lines(int nb, int Kn, int n3, const LineRule& R, const RowMat& D0, const RowMat& D1,
                  Scratch& sc) {
  const int nl = R.nl(), n0 = R.n0, n1 = nl - n0;
  size_lines(sc, nb, nl);
  if (n0 > 0)
    stage1(nb, n0, Kn, n3, R.Lc.data(), R.dLc.data(), D0.data(), D0.cols(), sc.A.data(),
           sc.A.cols(), sc.B.data(), sc.B.cols());
  if (n1 > 0)
    stage1(nb, n1, Kn, n3, R.Lc.col(n0).data(), R.dLc.col(n0).data(), D1.data(), D1.cols(),
           sc.A.row(n0).data(), sc.A.cols(), sc.B.row(n0).data(), sc.B.cols());
}

// Sum the kernel over the points of one line rule; the element data are in sc.D0/D1 (in the
// rule's orientation); sign: orientation of the rule's (s, t) relative to the element's.
// Stage 1: for every line, the 1-D interpolation across the lines (dense products
// Lc^T D: lines x (K nb)); stage 2: per point, length-nb dot products along the line.
template <Mode M>
void line_sum(int nb, int K_arg, const LineRule& R, const NodalBasis& basis, double sign,
              const Vector3d& x0, const Vector3d& u0, Scratch& sc, double* acc) {
  // the number of interpolated quantities is the mode's (a constant for the compiler)
  constexpr int K = uses_density(M) ? 6 : 3;
  if (K_arg != K) throw std::invalid_argument("line_sum: K does not match the mode");
  across_lines(nb, K * nb, 3 * nb, R, sc.D0, sc.D1, sc);
  at_simd_width(
      [&](auto w) { lines_stage2<M, decltype(w)::value>(nb, R, basis, sign, x0, u0, sc, acc); });
}

template void line_sum<Mode::Single>(int, int, const LineRule&, const NodalBasis&, double,
                                     const Vector3d&, const Vector3d&, Scratch&, double*);
template void line_sum<Mode::SingleNormal>(int, int, const LineRule&, const NodalBasis&, double,
                                           const Vector3d&, const Vector3d&, Scratch&, double*);
template void line_sum<Mode::Double>(int, int, const LineRule&, const NodalBasis&, double,
                                     const Vector3d&, const Vector3d&, Scratch&, double*);
template void line_sum<Mode::DoubleNormal>(int, int, const LineRule&, const NodalBasis&, double,
                                           const Vector3d&, const Vector3d&, Scratch&, double*);

void single_across(int nb, int nl, const double* Lc, const double* dLc, const RowMat& D, double* A,
                   long ldA, double* B, long ldB) {
  stage1(nb, nl, 6 * nb, 3 * nb, Lc, dLc, D.data(), D.cols(), A, ldA, B, ldB);
}

void single_sum(int nb, const LineRule& R, const ChebElement& ce, const Vector3d& x0, Scratch& sc,
                double* acc) {
  across_lines(nb, 6 * nb, 3 * nb, R, ce.cs, ce.ct, sc);
  const NodalBasis unused{nullptr, nullptr, nullptr};  // the Chebyshev sums use no nodal bases
  at_simd_width([&](auto w) {
    lines_stage2<Mode::Single, decltype(w)::value>(nb, R, unused, 1.0, x0, Vector3d::Zero(), sc,
                                                   acc);
  });
}

void single_rows_sum(int nb, const LineRule& R, const LineRows* rows, const Vector3d& x0,
                     double* acc) {
  at_simd_width([&](auto w) {
    constexpr int W = decltype(w)::value;
    for (int l = 0; l < R.nl(); ++l) {
      const int m = R.start[l + 1] - R.start[l];
      if (m == 0) continue;
      // -(base + scale off) exactly: T_k at the negated coordinate is (-1)^k T_k
      const double a = rows[l].along;
      single_line<W>(nb, m, rows[l].A, rows[l].B, a * R.base[l], a * R.scale[l], R.line_off(l),
                     R.wscale[l], R.line_wedge(l), x0.data(), acc);
    }
  });
}

// Single layer with the product g = J f interpolated from its nodal values (sc.D0/D1 hold x
// and g): 6 values per point instead of 12 (no tangents, no derivative bases).
void line_sum_jf(int nb, const LineRule& R, const NodalBasis& basis, const Vector3d& x0,
                 Scratch& sc, double* acc) {
  across_lines(nb, 6 * nb, 0, R, sc.D0, sc.D1, sc);  // no tangents: B is not made
  at_simd_width([&](auto w) { jf_lines_stage2<decltype(w)::value>(nb, R, basis, x0, sc, acc); });
}
}  // namespace capflow::stokes
