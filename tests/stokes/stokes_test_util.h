// Shared helpers for the stokes tests.
#pragma once

#include <Eigen/Dense>
#include <random>

namespace capflow::stokes::testing {

// n columns of independent uniform values in [-1, 1) (seeded): a rough density in which every
// node has its own value.
inline Eigen::Matrix3Xd random_density(int n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Eigen::Matrix3Xd u(3, n);
  for (int m = 0; m < n; ++m) u.col(m) = Eigen::Vector3d(uni(gen), uni(gen), uni(gen));
  return u;
}

}  // namespace capflow::stokes::testing
