// capflow/stokes/kernels: the free-space Stokes kernels (method.md section 2, paper eq. 5).
//
//   r = x - x0 (source minus target), r = |r|
//   Stokeslet  S_ij(x0, x)  = delta_ij / r + r_i r_j / r^3
//   Stresslet  T_ijk(x0, x) = -6 r_i r_j r_k / r^5
// Dimensionless; no 1/(8 pi) factors. With these, for lambda = 1 the velocity is
//   u(x0) = u_inf(x0) - (1/(8 pi Ca)) INT S(x0,x).f(x) dS(x).
// Both are singular at r = 0 (undefined result); callers keep x != x0.
#pragma once

#include <Eigen/Dense>

namespace capflow::stokes {

// S(x0, x) as a 3x3 matrix.
inline Eigen::Matrix3d stokeslet(const Eigen::Vector3d& x0, const Eigen::Vector3d& x) {
  const Eigen::Vector3d r = x - x0;
  const double ir = 1.0 / r.norm();
  return ir * Eigen::Matrix3d::Identity() + (ir * ir * ir) * r * r.transpose();
}

// S(x0, x) . f
inline Eigen::Vector3d stokeslet_apply(const Eigen::Vector3d& x0, const Eigen::Vector3d& x,
                                       const Eigen::Vector3d& f) {
  const Eigen::Vector3d r = x - x0;
  const double ir = 1.0 / r.norm();
  return ir * f + (ir * ir * ir * r.dot(f)) * r;
}

// T_ijk(x0, x) q_j n_k = -6 r_i (r.q)(r.n) / r^5
inline Eigen::Vector3d stresslet_apply(const Eigen::Vector3d& x0, const Eigen::Vector3d& x,
                                       const Eigen::Vector3d& q, const Eigen::Vector3d& n) {
  const Eigen::Vector3d r = x - x0;
  const double r2 = r.squaredNorm();
  const double ir5 = 1.0 / (r2 * r2 * std::sqrt(r2));
  return (-6.0 * r.dot(q) * r.dot(n) * ir5) * r;
}

// T_ijk(x0, x) n_k as a 3x3 matrix (i, j).
inline Eigen::Matrix3d stresslet_normal(const Eigen::Vector3d& x0, const Eigen::Vector3d& x,
                                        const Eigen::Vector3d& n) {
  const Eigen::Vector3d r = x - x0;
  const double r2 = r.squaredNorm();
  const double ir5 = 1.0 / (r2 * r2 * std::sqrt(r2));
  return (-6.0 * r.dot(n) * ir5) * r * r.transpose();
}

}  // namespace capflow::stokes
