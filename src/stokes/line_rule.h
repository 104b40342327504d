// capflow/stokes/line_rule: construction of the special (own and near element) quadrature rules
// as "lines" (boundary_integral.h explains the rules and why they are built as lines): the
// perpendicular/sinh polar rule around a point of the square, its radial nodes, and the
// Lagrange bases across its lines.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <vector>

#include "geometry/mesh.h"
#include "spectral/spectral.h"

namespace capflow::stokes {

constexpr int kMaxNb = 64;
constexpr int kMaxEdge = 256;  // Gauss points along an edge

// A special quadrature rule whose points lie on "lines" of constant s (lines [0, n0)) or
// constant t (lines [n0, nl)) in the canonical orientation of the square: the 1-D bases in
// the constant direction are shared by all points of a line. The points of a line are one of the
// rule's edge point sets (per edge of the square: the along-edge offsets `off` from the foot of
// the perpendicular and their weights `wedge`) scaled by the line's ray fraction u:
//   o = base + scale off[j],  w = wscale wedge[j]   (scale = u, wscale = u * radial weight).
// The kernel sums generate the points and their bases as they sum (line_sums.h).
struct LineRule {
  int n0 = 0;                               // number of constant-s lines
  std::vector<double> c;                    // per line: the constant coordinate
  std::vector<int> start;                   // per line: first point (size nl + 1)
  std::vector<double> base, scale, wscale;  // per line: o = base + scale off, w = wscale wedge
  std::vector<int> set;                     // per line: its edge point set
  std::vector<int> edge, radial;            // per line: its edge (0..3 as polar_rule) and ray node
  std::vector<int> set_start;               // per set: first entry of off / wedge (size sets + 1)
  std::vector<double> off, wedge;           // the edge point sets
  Eigen::MatrixXd Lc, dLc;                  // nb x nl: 1-D bases (and derivatives) at c
  int nl() const { return static_cast<int>(c.size()); }
  int np() const { return start.empty() ? 0 : start.back(); }
  // line l's edge point set: its first offset / weight and its size
  const double* line_off(int l) const { return off.data() + set_start[set[l]]; }
  const double* line_wedge(int l) const { return wedge.data() + set_start[set[l]]; }
};

// Radial rule of a polar rule's rays (the radial nodes (u, weight) on [0, 1] for one edge):
// h <= 0: Gauss-Legendre gr in u. h > 0 (scale h in u): the inner panel [0, u1], u1 = min(1, split)
// (split <= 0: u1 = 1), mapped by u = h sinh(sigma) with gi in sigma (further split into panels of
// length
// <= 6 in sigma), and the outer part [u1, 1] with go in u on each of out_panels panels whose
// lengths grow by 2 away from p0 (the sinh map alone under-resolves the polynomial part of the
// integrand far from p*). Near elements: h = the near-singular scale; own elements: a fixed
// grading scale (the ray integrand of a curved, non-uniformly stretched element has a complex
// singularity near u = 0 at ~ |J v|^2 / |J v . x_vv|, which plain Gauss in u resolves badly).
struct RadialOpt {
  const spectral::Rule* gi = nullptr;
  const spectral::Rule* go = nullptr;
  double split = 0.0;
  int out_panels = 1;
};

// Perpendicular/sinh polar rule around p0 = (s0, t0) in [-1,1]^2 (boundary_integral.h), built as
// lines: along every ray p0 -> edge point the coordinate perpendicular to that edge depends
// only on the ray fraction u, so for a fixed u the points of the two triangles on one edge
// form a line of constant s (edges s = +-1) or constant t (edges t = +-1).
// hu[edge] <= 0: plain Gauss in u (own element); hu > 0: radial sinh map u = hu sinh(sigma)
// (near elements), sigma in [0, asinh(1/hu)] split into panels of length <= 6.
// Edges in the order s = -1, s = +1 (constant-s lines), t = -1, t = +1 (constant-t lines).
// edge_rule (optional): the Gauss rule of a side from its sinh range asinh(L / d), instead of ge.
void polar_rule(double s0, double t0, const double* hu, const spectral::Rule& ge,
                const spectral::Rule& gr, LineRule& R, const RadialOpt& ro = RadialOpt(),
                const std::function<const spectral::Rule&(double)>* edge_rule = nullptr);

// The across bases of a line rule: Lc, dLc at the line coordinates (prod_w:
// spectral::product_weights of the element nodes). The matrices are resized only when they are
// too small or of another nb (scratch reused across calls and operators).
void fill_bases(const geometry::Mesh& mesh, const Eigen::VectorXd& prod_w, LineRule& R);

}  // namespace capflow::stokes
