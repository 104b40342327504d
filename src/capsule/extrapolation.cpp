#include "capsule/extrapolation.h"

#include <cmath>
#include <sstream>

namespace capflow::capsule {

OneModeExtrapolation extrapolate_one_mode(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1,
                                          const Eigen::Matrix3Xd& x2, double max_residual,
                                          double q_max) {
  if (x0.cols() != x1.cols() || x1.cols() != x2.cols())
    throw ExtrapolationError("one-mode extrapolation: the three states have different node counts");
  const Eigen::Matrix3Xd d1 = x1 - x0, d2 = x2 - x1;
  const double n11 = d1.squaredNorm();
  if (!(n11 > 0)) throw ExtrapolationError("one-mode extrapolation: the first two states are equal");
  OneModeExtrapolation r;
  r.q = d1.cwiseProduct(d2).sum() / n11;
  const double n22 = d2.squaredNorm();
  r.residual = n22 > 0 ? (d2 - r.q * d1).norm() / std::sqrt(n22) : 0.0;
  std::ostringstream why;
  if (!(r.q > 0 && r.q <= q_max))
    why << "the ratio of successive changes q = " << r.q << " is not in (0, " << q_max
        << "]: not a monotone decay, or too slow to extrapolate";
  else if (!(r.residual <= max_residual))
    why << "one mode does not describe the states: residual |d2 - q d1|/|d2| = " << r.residual
        << " > " << max_residual;
  if (!why.str().empty()) throw ExtrapolationError("one-mode extrapolation: " + why.str());
  r.factor = r.q / (1.0 - r.q);
  r.x = x2 + r.factor * d2;
  return r;
}

}  // namespace capflow::capsule
