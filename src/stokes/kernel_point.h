// capflow/stokes/kernel_point: one far-field quadrature point of the kernel sums of the identity
// checks and the double layer (inline; the special rules' loops in line_sums.cpp evaluate the same
// kernels on 8 points at once, and the single layer has its own vectorised far loop).
#pragma once

#include <cmath>

#include "stokes/kernel_mode.h"

namespace capflow::stokes {

// r = x - x0; (nx, ny, nz) = weight * J * unit normal; (fx, fy, fz)
// the density minus u(x0) (Double only). Adds the point's contribution to s0..s2 (s0..s8 for the
// 3x3 matrix of DoubleNormal, column-major).
template <Mode M>
[[gnu::always_inline]] inline void kernel_point(double rx, double ry, double rz, double nx,
                                                double ny, double nz, double fx, double fy,
                                                double fz, double& s0, double& s1, double& s2,
                                                double& s3, double& s4, double& s5, double& s6,
                                                double& s7, double& s8) {
  static_assert(M != Mode::Single, "the single layer uses single_line / far_single");
  const double ir = 1.0 / std::sqrt(rx * rx + ry * ry + rz * rz);
  const double ir3 = ir * ir * ir;
  if constexpr (M == Mode::SingleNormal) {
    const double b = (rx * nx + ry * ny + rz * nz) * ir3;
    s0 += ir * nx + b * rx;
    s1 += ir * ny + b * ry;
    s2 += ir * nz + b * rz;
  } else if constexpr (M == Mode::Double) {
    const double rq = rx * fx + ry * fy + rz * fz;
    const double a = -6.0 * rq * (rx * nx + ry * ny + rz * nz) * ir3 * ir * ir;
    s0 += a * rx;
    s1 += a * ry;
    s2 += a * rz;
  } else {
    const double a = -6.0 * (rx * nx + ry * ny + rz * nz) * ir3 * ir * ir;
    s0 += a * rx * rx;
    s1 += a * ry * rx;
    s2 += a * rz * rx;
    s3 += a * rx * ry;
    s4 += a * ry * ry;
    s5 += a * rz * ry;
    s6 += a * rx * rz;
    s7 += a * ry * rz;
    s8 += a * rz * rz;
  }
}

// Adds the sums of kernel_point to the accumulator (9 entries for DoubleNormal, else 3).
template <Mode M>
inline void add_sums(double* acc, double s0, double s1, double s2, double s3, double s4, double s5,
                     double s6, double s7, double s8) {
  acc[0] += s0;
  acc[1] += s1;
  acc[2] += s2;
  if constexpr (M == Mode::DoubleNormal) {
    acc[3] += s3;
    acc[4] += s4;
    acc[5] += s5;
    acc[6] += s6;
    acc[7] += s7;
    acc[8] += s8;
  }
}

}  // namespace capflow::stokes
