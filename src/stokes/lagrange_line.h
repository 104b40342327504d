// capflow/stokes/lagrange_line: the register-blocked pieces shared by the special rules' stage-2
// loops (line_sums.cpp, matrix_sums.cpp): vectors of W points of one rule line, the Lagrange bases
// along the line made in registers, the interpolated position, density and tangents, and the
// weighted normal; the width dispatch. Inline only: each cloned loop (spectral/target_clones.h)
// compiles them for its own architecture. Internal to src/stokes.
#pragma once

#include <cmath>
#include <type_traits>

#include "spectral/simd_width.h"
#include "stokes/line_rule.h"
#include "stokes/line_sums.h"

namespace capflow::stokes::detail {

// Stage 2 works on blocks of kBlock = 8 points: the kernel's square root and division are
// latency-bound, and 8 independent lanes hide more of it than 4 (NE=10 NB=12 single layer ~1.45x,
// docs/performance.md). A block is one vector of W = 8 doubles in the AVX-512 clones, and
// kBlock / W vectors of W = 4 (AVX2) or 2 (SSE) in the others (spectral/simd_width.h), each part
// with its own sums: lane q of part h is lane h W + q of the block, so every width adds the same
// numbers in the same order and gives the same bits.
constexpr int kBlock = 8;
template <int W>
struct VecOf;
template <>
struct VecOf<8> {
  typedef double type __attribute__((vector_size(64)));
};
template <>
struct VecOf<4> {
  typedef double type __attribute__((vector_size(32)));
};
template <>
struct VecOf<2> {
  typedef double type __attribute__((vector_size(16)));
};
template <int W>
using vec = typename VecOf<W>::type;  // W doubles (a dependent vector_size alias is not a vector)
template <int W>
constexpr int kParts = kBlock / W;  // vectors per block

// Calls f(std::integral_constant<int, W>{}) with this CPU's kernel width W.
template <class F>
inline void at_simd_width(F&& f) {
  switch (spectral::simd_width()) {
    case 8:
      f(std::integral_constant<int, 8>{});
      break;
    case 4:
      f(std::integral_constant<int, 4>{});
      break;
    default:
      f(std::integral_constant<int, 2>{});
  }
}

// One line of a special rule for the modes with Lagrange bases along the line: the stage-1 rows
// A (x, and the density if there is one, at the along nodes: K nb) and B (d/d(across) x: 3 nb),
// and the line's m points o_j = base + scale off[j] with weights w_j = wscale wedge[j].
struct LagrangeLine {
  const double* A;
  const double* B;
  double base, scale;
  const double* off;
  double wscale;
  const double* wedge;
  int m;
};

// r2 <- 1 / sqrt(r2), lane by lane (in place: a vector return value would change the baseline
// clone's ABI)
template <int W>
[[gnu::always_inline]] inline void inv_sqrt(vec<W>& r2) {
  for (int q = 0; q < W; ++q) r2[q] = 1.0 / std::sqrt(r2[q]);
}

// The derivative along a line at its along nodes, dA[c nb + i] = sum_k D(i, k) A[c nb + k] for the
// position (c < 3): exact for the line's polynomial of degree nb - 1, so its interpolant is the
// derivative of the position's (no derivative bases at the points).
[[gnu::always_inline]] inline void along_derivative(int nb, const double* A, const double* D,
                                                    double* dA) {
  for (int i = 0; i < 3 * nb; ++i) dA[i] = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < nb; ++k) {
      const double a = A[c * nb + k];
      for (int i = 0; i < nb; ++i) dA[c * nb + i] += D[i + k * nb] * a;
    }
}

// The interpolated values at the points p0 .. p0 + W - 1 of a line (lanes past its end: weight 0,
// pad 1): the position X, the density F (Density) and the derivatives across (Ac, from B) and
// along (Al, from dA) (Tangents). The Lagrange bases at each point are made in registers by the
// product formula of spectral::lagrange_bases (prefix products times the weight c_j, then suffix
// products), so no rule stores point bases and no near rule evaluates them into memory.
template <bool Density, bool Tangents, int W>
[[gnu::always_inline]] inline void lagrange_block(int nb, const LagrangeLine& ln, const double* dA,
                                                  const NodalBasis& nbas, int p0, vec<W>& wq,
                                                  vec<W>& pad, vec<W>* X, vec<W>* F, vec<W>* Ac,
                                                  vec<W>* Al) {
  using vl = vec<W>;
  const vl kZero = vec<W>{}, kOne = vec<W>{} + 1.0;
  vl ov;
  for (int q = 0; q < W; ++q) {
    const bool in = p0 + q < ln.m;
    ov[q] = in ? ln.base + ln.scale * ln.off[p0 + q] : 0.0;
    wq[q] = in ? ln.wscale * ln.wedge[p0 + q] : 0.0;
    pad[q] = in ? 0.0 : 1.0;
  }
  vl pre[kMaxNb];  // c_j prod_{k < j} (o - x_k)
  vl P = kOne;
  for (int j = 0; j < nb; ++j) {
    pre[j] = nbas.weights[j] * P;
    P = P * (ov - nbas.nodes[j]);
  }
  for (int c = 0; c < 3; ++c) {
    X[c] = kZero;
    if constexpr (Density) F[c] = kZero;
    if constexpr (Tangents) Ac[c] = Al[c] = kZero;
  }
  P = kOne;  // prod_{k > j} (o - x_k)
  const double* A = ln.A;
  const double* B = ln.B;
  for (int j = nb - 1; j >= 0; --j) {
    const vl L = pre[j] * P;
    P = P * (ov - nbas.nodes[j]);
    for (int c = 0; c < 3; ++c) X[c] += A[c * nb + j] * L;
    if constexpr (Density)
      for (int c = 0; c < 3; ++c) F[c] += A[(3 + c) * nb + j] * L;
    if constexpr (Tangents)
      for (int c = 0; c < 3; ++c) {
        Ac[c] += B[c * nb + j] * L;
        Al[c] += dA[c * nb + j] * L;
      }
  }
}

// w J n at the block's points: sg (x_across x x_along) times the weight.
template <int W>
[[gnu::always_inline]] inline void weighted_normal(const vec<W>* Ac, const vec<W>* Al, vec<W> wq,
                                                   double sg, vec<W>* n) {
  const vec<W> ws = sg * wq;
  n[0] = ws * (Ac[1] * Al[2] - Ac[2] * Al[1]);
  n[1] = ws * (Ac[2] * Al[0] - Ac[0] * Al[2]);
  n[2] = ws * (Ac[0] * Al[1] - Ac[1] * Al[0]);
}

// The sum of a block's kBlock lanes, held in kParts<W> vectors, in one order for every width.
template <int W>
[[gnu::always_inline]] inline double hsum(const vec<W>* v) {
  double l[kBlock];
  for (int h = 0; h < kParts<W>; ++h)
    for (int q = 0; q < W; ++q) l[h * W + q] = v[h][q];
  return ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]));
}

// The part of a block that the points (or lines) from p0 on fall in.
template <int W>
constexpr int part_of(int p0) {
  return (p0 / W) % kParts<W>;
}

}  // namespace capflow::stokes::detail
