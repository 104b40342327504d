// capflow/stokes/lagrange_line: the register-blocked pieces shared by the special rules' stage-2
// loops (line_sums.cpp, matrix_sums.cpp): blocks of kW points of one rule line, the Lagrange
// bases along the line made in registers, the interpolated position, density and tangents, and the
// weighted normal. Inline only: each cloned loop (spectral/target_clones.h) compiles them for its
// own architecture. Internal to src/stokes.
#pragma once

#include <cmath>

#include "stokes/line_rule.h"
#include "stokes/line_sums.h"

namespace capflow::stokes::detail {

// Stage 2 works on blocks of 8 points (one 512-bit vector on AVX-512, two 256-bit halves on
// AVX2): the kernel's square root and division are latency-bound, and 8 independent lanes hide
// more of it than 4 (NE=10 NB=12 single layer ~1.45x, docs/performance.md).
constexpr int kW = 8;
typedef double vl __attribute__((vector_size(8 * kW)));

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

constexpr vl kZero = {0, 0, 0, 0, 0, 0, 0, 0}, kOne = {1, 1, 1, 1, 1, 1, 1, 1};

// r2 <- 1 / sqrt(r2), lane by lane (in place: a vector return value would change the baseline
// clone's ABI)
[[gnu::always_inline]] inline void inv_sqrt(vl& r2) {
  for (int q = 0; q < kW; ++q) r2[q] = 1.0 / std::sqrt(r2[q]);
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

// The interpolated values at the points p0 .. p0 + kW - 1 of a line (lanes past its end: weight 0,
// pad 1): the position X, the density F (Density) and the derivatives across (Ac, from B) and
// along (Al, from dA) (Tangents). The Lagrange bases at each point are made in registers by the
// product formula of spectral::lagrange_bases (prefix products times the weight c_j, then suffix
// products), so no rule stores point bases and no near rule evaluates them into memory.
template <bool Density, bool Tangents>
[[gnu::always_inline]] inline void lagrange_block(int nb, const LagrangeLine& ln, const double* dA,
                                                  const NodalBasis& nbas, int p0, vl& wq, vl& pad,
                                                  vl* X, vl* F, vl* Ac, vl* Al) {
  vl ov;
  for (int q = 0; q < kW; ++q) {
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
[[gnu::always_inline]] inline void weighted_normal(const vl* Ac, const vl* Al, vl wq, double sg,
                                                   vl* n) {
  const vl ws = sg * wq;
  n[0] = ws * (Ac[1] * Al[2] - Ac[2] * Al[1]);
  n[1] = ws * (Ac[2] * Al[0] - Ac[0] * Al[2]);
  n[2] = ws * (Ac[0] * Al[1] - Ac[1] * Al[0]);
}

[[gnu::always_inline]] inline double hsum(const vl& v) {
  return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
}

}  // namespace capflow::stokes::detail
