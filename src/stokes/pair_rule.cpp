// capflow/stokes/pair_rule: see pair_rule.h.
#include "stokes/pair_rule.h"

namespace capflow::stokes {

PairRule choose_pair_rule(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x, int e,
                          const ElementBounds& b, const Eigen::Vector3d& x0,
                          const PairThresholds& t) {
  PairRule r;
  // beyond mid from every node's sphere: far tier 0 without looking closer
  if ((x0 - b.centre).norm() - b.radius >= t.mid) return r;
  // The distance h of x0 to the element lies in [d - cell, d], d the distance to the nearest
  // node: the nearest point is searched only when h may be below the near threshold (the near
  // rule needs p*) or the interval straddles a tier's threshold.
  int best = 0;
  const double d = geometry::nearest_node(mesh, x, e, x0, &best), lo = d - b.cell;
  const double thresholds[2] = {t.inner, t.mid};
  bool decided = lo >= t.near;
  for (double th : thresholds) decided = decided && (th <= 0.0 || lo >= th || d < th);
  if (decided) {
    r.tier = d < t.mid ? (d < t.inner ? 2 : 1) : 0;
    return r;
  }
  r.np = geometry::nearest_point(mesh, x, e, x0, best);
  r.searched = true;
  r.near = r.np.h < t.near;
  r.tier = r.np.h < t.mid ? (r.np.h < t.inner ? 2 : 1) : 0;
  return r;
}

}  // namespace capflow::stokes
