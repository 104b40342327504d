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

  // The lines of the rules in the element's orientation. Every rule has the same ray nodes u_q
  // (q < ray_nodes(); 0 with own_tolerance > 0, whose rules differ), so the constant-s lines of
  // every node (i, j) of a column i lie at x_i + u_q (side - x_i), side = -1 or +1, whatever j
  // (likewise the constant-t lines of a row j): the single layer interpolates across them once
  // per element and node row for all its targets (own_lines.h). row_bases(i): the 1-D bases at
  // those lines (nb x 2 ray_nodes(): column q for side -1, ray_nodes() + q for side +1),
  // row_derivs(i) their derivatives.
  int ray_nodes() const { return ray_nodes_; }
  const Eigen::MatrixXd& row_bases(int i) const { return row_bases_[i]; }
  const Eigen::MatrixXd& row_derivs(int i) const { return row_derivs_[i]; }
  // Line l of a rule used with symmetry sym, in the element's orientation: a line of constant s
  // (dir 0) or t (dir 1) on side 0 (-1) or 1 (+1) of the node, ray node q; the element's
  // coordinate along the line is `along` times the rule's.
  struct ElementLine {
    int dir, side, q;
    double along;
  };
  static ElementLine element_line(const LineRule& r, int l, int sym) {
    const int cd = r.edge[l] >> 1, f = r.edge[l] & 1;  // the rule's direction and side
    const bool fs = sym & 1, ft = sym & 2, sw = sym & 4;
    const int dir = sw ? 1 - cd : cd;  // a swap exchanges the rule's s and t
    const bool flip = dir == 0 ? fs : ft, flip_along = dir == 0 ? ft : fs;
    return ElementLine{dir, flip ? 1 - f : f, r.radial[l], flip_along ? -1.0 : 1.0};
  }

  int count() const { return static_cast<int>(rules_.size()); }
  long points() const;
  int max_lines() const;  // lines of the largest rule

 private:
  void make_row_bases(const geometry::Mesh& mesh, const Eigen::VectorXd& prod_w);

  std::vector<LineRule> rules_;               // one per canonical node
  std::vector<int> canon_rule_;               // (i + nb j) -> rule index
  std::vector<int> canon_sym_;                // (i + nb j) -> symmetry bits
  std::vector<std::vector<int>> canon_perm_;  // per symmetry (8)
  int ray_nodes_ = 0;
  std::vector<Eigen::MatrixXd> row_bases_, row_derivs_;  // per node index
};

}  // namespace capflow::stokes
