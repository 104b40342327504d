// capflow/stokes/pair_rule: which rule sums element e for target x0 (a (target, element) pair
// that is not the target's own element) - a pure decision from the element's bounds
// (stokes/element_bounds.h) and, only where they cannot decide, a nearest-point search:
//   near    distance h < near (the near-singular polar rule about the nearest point p*, which
//           the choice hands on);
//   far 2   near <= h < inner (the single layer's inner mid tier, single_nq_mid);
//   far 1   inner <= h < mid  (nq_mid);
//   far 0   h >= mid          (nq_far),
// the thresholds in units of length (factors times the element's size, QuadratureOptions);
// inner = 0 for the operators without the inner tier. The nearest node's distance d bounds h:
// h lies in [d - cell, d], so the search runs only when that interval straddles a threshold -
// the choice is the one the exact h would give (tests/stokes/test_pair_rule.cpp).
#pragma once

#include <Eigen/Dense>

#include "geometry/element_search.h"
#include "geometry/mesh.h"
#include "stokes/element_bounds.h"

namespace capflow::stokes {

struct PairThresholds {
  double near = 0;   // below: the near rule
  double inner = 0;  // below (and not near): far tier 2; 0: no inner tier
  double mid = 0;    // below (and not near or inner): far tier 1; else far tier 0
};

struct PairRule {
  bool near = false;
  int tier = 0;           // the far tier when not near: 0 nq_far, 1 nq_mid, 2 single_nq_mid
  bool searched = false;  // a nearest-point search was needed
  geometry::NearestPoint np;  // the nearest point (when searched; the near rule needs it)
};

PairRule choose_pair_rule(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x, int e,
                          const ElementBounds& b, const Eigen::Vector3d& x0,
                          const PairThresholds& t);

}  // namespace capflow::stokes
