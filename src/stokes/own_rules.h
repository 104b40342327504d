// capflow/stokes/own_rules: the own-element rules of the boundary operators (boundary_integral.h):
// one polar line rule per canonical node (i <= j <= (nb-1)/2; the other nodes of the element
// map to one of these by the 8 symmetries of the square, and their element data are permuted
// instead), with the 1-D bases across its lines; and, with own_tolerance > 0, the
// selection of each canonical node's orders (the fewest points within the tolerance of a
// high-order rule, probed on every element of the sphere and an ellipsoid; cached process-wide
// per mesh type and options).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "geometry/mesh.h"
#include "stokes/line_rule.h"

namespace capflow::stokes {

struct QuadratureOptions;

class OwnRules {
 public:
  // opt: resolved options (resolve_defaults); prod_w: spectral::product_weights of the nodes.
  OwnRules(const geometry::Mesh& mesh, const QuadratureOptions& opt, const Eigen::VectorXd& prod_w);

  // The rule of local node loc = i + nb j of an element, the symmetry that maps it to its
  // canonical node (bits: 1 flip s, 2 flip t, 4 swap) and that symmetry's orientation sign.
  const LineRule& rule(int loc) const { return rules_[canon_rule_[loc]]; }
  int symmetry(int loc) const { return canon_sym_[loc]; }
  static double sign(int sym) {
    return ((sym & 1) ? -1.0 : 1.0) * ((sym & 2) ? -1.0 : 1.0) * ((sym & 4) ? -1.0 : 1.0);
  }
  // Per symmetry: canonical (a + nb b) -> local node of the element.
  const int* permutation(int sym) const { return canon_perm_[sym].data(); }

  int count() const { return static_cast<int>(rules_.size()); }
  long points() const;
  int max_lines() const;  // lines of the largest rule

 private:
  std::vector<LineRule> rules_;               // one per canonical node
  std::vector<int> canon_rule_;               // (i + nb j) -> rule index
  std::vector<int> canon_sym_;                // (i + nb j) -> symmetry bits
  std::vector<std::vector<int>> canon_perm_;  // per symmetry (8)
};

}  // namespace capflow::stokes
