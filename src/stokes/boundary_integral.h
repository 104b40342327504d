// capflow/stokes/boundary_integral: single- and double-layer Stokes operators on a surface in
// the spectral boundary element representation (method.md sections 2 and 4).
//
// Operators (kernels in stokes/kernels.h, r = x - x0, no 1/(8 pi) factors):
//   single layer   SL[f](x0) = INT S(x0,x).f(x) dS(x)
//   double layer   DL[u](x0) = INT T(x0,x).(u(x) - u(x0)).n(x) dS(x)     (x0 a node)
// so that for lambda = 1: u = u_inf - SL[f] / (8 pi Ca), and for lambda != 1 the principal
// value is PV INT u.T.n dS = DL[u](x0) - 4 pi u(x0).
// x, f, u are nodal values (3 x mesh.num_local()) interpolated element-wise (paper eq. 15);
// n is the exact unit normal of that interpolant, dS = |x_xi x x_eta| dxi deta.
//
// Quadrature, per target x0 and element E:
//  * own elements (x0 is a node of E at parameters p0 = (xi0, eta0), one entry per element of
//    the node's coincidence class: 1, 2, 3 or 4): [-1,1]^2 is split by the perpendiculars from
//    p0 to the 4 edges into right triangles (8 interior, 4 on an edge, 2 at a corner); in each,
//    the edge coordinate is s = d sinh(tau) (d = distance from p0 to that edge) with
//    Gauss points in tau by the side's range (own_edge_base, at most `n_edge`), and the ray
//    p0 -> edge point has a graded panel on [0, own_split] (u = own_grading sinh(sigma),
//    `n_radial_inner` points) and `n_radial` Gauss points on [own_split, 1] in the fraction u
//    (polar Jacobian u d ds du cancels 1/r; Muldowney & Higdon 1995).
//    Points and weights depend only on p0, i.e. on the node's (i, j) in the element, so these
//    rules (with the 1-D bases across their lines) are precomputed once per mesh
//    (own_rules.h), for the (i, j) up to the 8 symmetries of the square (the element's nodal
//    data are permuted instead).
//  * near elements (nearest point p* of E to x0 at distance h < near_factor * size(E), size =
//    mean length of E's longer family of coordinate lines): p* by a projected Newton with an
//    active set (a boundary coordinate whose gradient points outwards is held fixed), then the
//    same perpendicular/sinh split around p*. Along the rays to one edge the fraction u is
//    split at u1 = near_split: [0, u1] with u = hu sinh(sigma) (`n_radial_near` Gauss points
//    in sigma, panels of length <= 6), hu = h / max |J v| over the rays v to the edge's ends
//    (J = [x_xi x_eta] at p*; hu bounds the near-singular scale of every ray of that edge);
//    [u1, 1] with `near_out_panels` panels (lengths growing by 2) of `n_radial_near_out` Gauss
//    points in u (the sinh map alone under-resolves the
//    polynomial part far from p*). `n_edge_near` points in tau. Recomputed per call.
//    (The single layer: single_near_factor and single_nq_mid instead of near_factor, nq_mid.)
//  * far elements: Gauss-Legendre, nq_mid x nq_mid for near_factor <= h/size < mid_factor
//    (h from the Newton above), nq_far x nq_far beyond (bounding-sphere test). The Newton
//    search runs only where the nearest node does not decide the tier (h lies within a cell
//    diagonal of that node's distance). The single layer's inner mid tier is made per call only
//    for the elements a target of the call may reach by the same bounds (element_bounds.h).
// Every special rule is a set of "lines": for a fixed u, the points of the two triangles on
// one edge share the coordinate perpendicular to that edge (constant s for the edges
// s = +-1, constant t for t = +-1). Interpolation is done in two stages: per line, the 1-D
// interpolation across the lines (element data nb x 6nb times the 1-D bases: x, f and
// d/d(across) x), then per point length-nb sums along the line (x, f, d/d(along) x and
// d/d(across) x), i.e. ~12 nb multiply-adds per point instead of ~9 nb^2. The own rules of the
// nodes of one element column (row) share their constant-s (-t) lines in the element's
// orientation, so the single layer does stage 1 of the own lines once per element and node row
// for all the targets of a call (own_lines.h). The single layer
// holds the element data along the lines in Chebyshev coefficients and evaluates T_k, T_k' at
// each point by recurrences (no per-point bases); the other modes use Lagrange bases along the
// line, made at each point in registers by the product formula (none stored or read), which keep
// the double layer's near-singular r.n accurate where the Chebyshev sum would lose digits
// (line_sums.h). The hot loops (stage 1, stage 2 + kernel in blocks of 8 points held in vectors
// of the CPU's width, spectral/simd_width.h, far sums of the single layer) are compiled for
// x86-64-v4, x86-64-v3 and the baseline and chosen at load time. Options: own_tolerance > 0
// selects the own rule per canonical node (fewest points meeting the tolerance against a high-order
// rule on the sphere and an ellipsoid; own_rules.h); interpolate_jf interpolates J f from its nodal
// values (6 values per point instead of 12: ~1.8x faster, but it changes the discrete operator by
// ~1e-5 relative at NB=10).
//
// Threading: every call runs an OpenMP loop over targets (omp_get_max_threads threads; the
// caller limits with omp_set_num_threads, and stokes::set_thread_cap caps every call's team from
// any thread: stokes/thread_cap.h), after two set-up phases of tasks: phase 1 what needs only
// x (the far tiers' surface data, the Chebyshev element data of x, the element bounds), phase 2
// what needs the density (the far tiers' density rows, the reached inner tiers), then the own
// lines' stage 1. A density given as a function (single_layer with a DensityFn) is computed by
// the team's first thread during phase 1. Objects are immutable after construction and
// may be used from several threads; each call allocates its own scratch once per thread.
// Failure modes: wrong matrix sizes or target indices throw std::invalid_argument.
//
// Files, one job each: line_rule (construction of the special rules), own_rules (the own rules
// per canonical node and their selection), own_lines (the single layer's own lines after stage 1,
// shared by the targets of a node row), line_sums (kernel sums over a special rule on one
// element), far_field (the far tiers), element_bounds (the node bounds the tiers are decided
// with), kernel_point / kernel_mode (one point of the non-single-
// layer sums; which sum), this file (the options and the operator: which rule for which
// (target, element), the loop over targets); the nearest point of a near element is
// geometry::nearest_point (geometry/element_search.h).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <vector>

#include "geometry/mesh.h"
#include "spectral/spectral.h"
#include "stokes/far_field.h"
#include "stokes/kernel_mode.h"
#include "stokes/own_rules.h"

namespace capflow::stokes {

using Eigen::Matrix3Xd;
using Eigen::MatrixXd;

struct QuadratureOptions {
  // Defaults measured on the unit sphere (NE=6/10/14, NB=12/16: 1e-8 in INT S.n dS and
  // INT T.n dS at interior and next-to-edge nodes) and against a high-order reference on
  // deformed shapes (tests/stokes/test_stokes_accuracy.cpp: <= 2.5e-8 relative at NE=6 NB=10).
  int nq_far = 0;  // Gauss-Legendre per direction on far elements; 0 -> (3nb+19)/2
  int nq_mid = 0;  // ... on elements at near_factor..mid_factor sizes; 0 -> 3 nb + 2
  int n_edge = 0;  // own element: points along the edge coordinate; 0 -> 2 nb
                   // (3 nb if some element is longer than 2:1, as the NE=14 rows)
  // Own element, along each ray: a graded inner panel [0, own_split] (u = own_grading
  // sinh(sigma), n_radial_inner Gauss points in sigma) and n_radial Gauss points on
  // [own_split, 1]; n_radial_inner = 0: plain Gauss in u on [0, 1] (the rule before
  // 2026-12-02, which left 4e-5 .. 2.5e-3 relative error in SL[f] at deformed capsule states
  // against 3e-7 .. 5e-5 now: docs/performance.md, "Own and near radial rules").
  int n_radial_inner = -1;  // -1 -> nb + 2
  int n_radial = 0;         // 0 -> nb (graded) or nb + 4 (plain)
  double own_split = 0.5;
  double own_grading = 0.2;
  int n_edge_near = 0;    // near elements: along the edge; 0 -> nb + 6 (2 nb if > 2:1)
  int n_radial_near = 0;  // near elements: sinh panel [0, near_split] of each ray; 0 -> nb
  // near elements: near_out_panels Gauss panels on [near_split, 1] (lengths growing by 2),
  // n_radial_near_out points each; 0 -> max(4, nb - 2)
  int n_radial_near_out = 0;
  int near_out_panels = 2;
  double near_split = 0.3;   // ray fraction where the near radial rule switches (<= 0: none)
  double near_factor = 0.2;  // near when dist(x0, E) < near_factor * size(E)
  double mid_factor = 0.5;   // nq_mid when dist(x0, E) < mid_factor * size(E)
  // The single layer's tiers (its 1/r kernel needs the near rules closer to the surface than
  // the 1/r^2 of the double layer and INT T.n; measured on the sphere identities and deformed
  // shapes, docs/performance.md): near when dist < single_near_factor * size(E), then Gauss
  // with single_nq_mid points per direction up to single_mid_split * size(E), nq_mid up to
  // mid_factor * size(E).
  double single_near_factor = 0.1;
  int single_nq_mid = 0;  // 0 -> 4 nb + 4
  double single_mid_split = 0.2;
  // > 0: per-node own rules (fewest points within this relative tolerance of a (3nb, 2nb+4)
  // rule; cached per mesh type). Off by default: at 3e-9 it removes 40-45 % of the own points
  // but misses the 1e-8 INT T.n identity at NE=10 NB=12 and takes seconds at NE=14.
  double own_tolerance = 0.0;
  // Own element: the Gauss order along a side of the polar rule (L the side's length along its
  // edge, d the node's distance to the edge, rho = asinh(L / d) the side's sinh range) is
  // min(n_edge, ceil(nb (own_edge_base + own_edge_slope rho))): 2 nb only on the long, thin
  // sides of nodes near an edge. own_edge_base <= 0: n_edge on every side. The same errors as
  // n_edge everywhere on the sphere identities and the deformed shapes of tests/stokes, with
  // 29-49 % fewer own points (docs/performance.md, "Own edge orders by the sinh range").
  double own_edge_base = 0.7;
  double own_edge_slope = 0.7;
  bool interpolate_jf = false;  // single layer: interpolate J f (faster, less accurate)
};

// The options with every order left at 0 (or -1) replaced by its default for the mesh, and
// validated (std::invalid_argument): what BoundaryOperators(mesh, options).options() holds.
QuadratureOptions resolve_defaults(const geometry::Mesh& mesh, QuadratureOptions options);

// Factors on the quadrature orders of resolved options (BoundaryOperators::options()): far
// Gauss order, own-element orders, near-element orders, mid Gauss order (<= 0: as far); each
// order rounded, at least 2. A reference for accuracy studies is scale_orders(ops.options(),
// {3, 3, 3}) or scale_orders(resolve_defaults(mesh, {}), {3, 3, 3}).
struct OrderScales {
  double far = 1.0, own = 1.0, near = 1.0, mid = 0.0;
};
QuadratureOptions scale_orders(const QuadratureOptions& resolved, const OrderScales& k);

// Counts of one call (kernel evaluations = source points x targets), returned through the
// optional `stats` argument of the operators.
struct OperatorStats {
  long targets = 0;
  long far_pairs = 0;      // far Gauss points summed
  long own_pairs = 0;      // own-element polar points
  long near_pairs = 0;     // near-singular points
  long near_elements = 0;  // (target, element) pairs treated as near
  long searches = 0;       // nearest-point searches (near and mid tier candidates)
  // Single layer: the elements whose inner mid tier (single_nq_mid) was made, and of those the
  // ones a target took although the bound of element_bounds.h said none would reach it.
  long inner_far_elements = 0;
  long inner_far_late = 0;
  // Single layer: the floating-point operations of its kernel sums, counted from the code of the
  // hot loops (line_sums.cpp single_line and stage1, far_field.cpp far_single; an FMA is 2, a
  // square root or division 1): per special point 28 nb + 36 (stage 2 with the Chebyshev
  // recurrences and the kernel), per line 2 nb (pad8(6 nb) + pad8(3 nb)) + 3 nb (stage 1), per
  // far point 31. The set-up work (far data, nearest points, rules) is not counted. 0 for the
  // other modes.
  double flops = 0;
  long pairs() const { return far_pairs + own_pairs + near_pairs; }
};

// A linear expansion of values given at `columns` points to every local node: node m holds
// sign[m] (component by component) times the value at column[m] (capsule::SymmetryMap: the values
// at the symmetry targets mirrored to every node).
struct NodeExpansion {
  int columns = 0;
  std::vector<int> column;            // per local node, in [0, columns)
  std::vector<Eigen::Vector3d> sign;  // per local node
};

template <Mode M>
class OperatorCall;  // stokes/operator_call.h: one application

class BoundaryOperators {
 public:
  BoundaryOperators(const geometry::Mesh& mesh, QuadratureOptions options = {});

  const geometry::Mesh& mesh() const { return mesh_; }
  const QuadratureOptions& options() const { return opt_; }  // with the defaults resolved

  // SL[f] at every local node (3 x num_local; coincident nodes get the same value, computed
  // once per coincidence class).
  Matrix3Xd single_layer(const Matrix3Xd& x, const Matrix3Xd& f,
                         OperatorStats* stats = nullptr) const;
  // SL[f] at the listed local nodes only: out.col(k) = SL[f](x.col(targets[k])).
  void single_layer(const Matrix3Xd& x, const Matrix3Xd& f, const std::vector<int>& targets,
                    Matrix3Xd& out, OperatorStats* stats = nullptr) const;
  // The same with f made during the call by density(f) (3 x num_local): the first thread of the
  // call's team runs it while the others make what needs only x (the far tiers' surface data,
  // the element bounds), so that a serial density (the membrane traction) does not leave the
  // other threads idle. The result is that of the call with f. An exception of density
  // propagates; a density of the wrong size throws std::invalid_argument.
  using DensityFn = std::function<void(Matrix3Xd& f)>;
  void single_layer(const Matrix3Xd& x, const DensityFn& density, const std::vector<int>& targets,
                    Matrix3Xd& out, OperatorStats* stats = nullptr) const;
  // SL[f] at arbitrary points (on, near or off the surface): every element is near or far.
  Matrix3Xd single_layer_at(const Matrix3Xd& x, const Matrix3Xd& f, const Matrix3Xd& points,
                            OperatorStats* stats = nullptr) const;

  // DL[u] at every local node / at the listed local nodes.
  Matrix3Xd double_layer(const Matrix3Xd& x, const Matrix3Xd& u,
                         OperatorStats* stats = nullptr) const;
  void double_layer(const Matrix3Xd& x, const Matrix3Xd& u, const std::vector<int>& targets,
                    Matrix3Xd& out, OperatorStats* stats = nullptr) const;

  // The double layer at the listed local nodes as a matrix A (3 targets x 3 columns, row-major):
  // row 3 k + i is component i of DL at targets[k], column 3 c + j component j of the value at
  // column c: DL[u](targets) = A vec(v) for u = expansion(v) (expansion null: v = u, the local
  // nodes). The same quadrature as double_layer (equal to rounding); costs about one double_layer
  // call, after which each application is a matrix-vector product (capsule/viscosity_ratio.h).
  RowMat double_layer_matrix(const Matrix3Xd& x, const std::vector<int>& targets,
                             const NodeExpansion* expansion = nullptr,
                             OperatorStats* stats = nullptr) const;

  // Identity checks with the exact normal n of the interpolated surface (no nodal density):
  //   INT S.n dS at the listed nodes (3 x targets), and
  //   INT T_ijk n_k dS (column k holds the 3x3 matrix, column-major, 9 x targets).
  Matrix3Xd single_layer_normal(const Matrix3Xd& x, const std::vector<int>& targets) const;
  MatrixXd double_layer_normal(const Matrix3Xd& x, const std::vector<int>& targets) const;

  // Plain nq x nq Gauss-Legendre on every element, at arbitrary points (accurate only for
  // points well off the surface).
  static Matrix3Xd single_layer_gauss(const geometry::Mesh& mesh, const Matrix3Xd& x,
                                      const Matrix3Xd& f, const Matrix3Xd& points, int nq);

  // Number of precomputed own-element rules and their total points (for memory reports).
  int own_rule_count() const { return own_.count(); }
  long own_rule_points() const { return own_.points(); }

  using Mode = stokes::Mode;

 private:
  template <Mode>
  friend class OperatorCall;
  // One application of mode M (stokes/operator_call.h).
  template <Mode M>
  OperatorStats apply(const Matrix3Xd& x, const Matrix3Xd* dens,
                      const std::vector<int>* node_targets, const Matrix3Xd* point_targets,
                      MatrixXd& out, RowMat* matrix = nullptr,
                      const NodeExpansion* expansion = nullptr,
                      const DensityFn* make_density = nullptr) const;

  const geometry::Mesh& mesh_;
  QuadratureOptions opt_;
  Eigen::VectorXd prod_w_;  // spectral::product_weights of the element nodes (rule bases)
  Eigen::MatrixXd cheb_;    // spectral::chebyshev_matrix of the element nodes
  OwnRules own_;
  FarBasis far_basis_[3];  // the far tiers' Gauss rules: 0 nq_far, 1 nq_mid, 2 single_nq_mid
  // The near rules' Gauss rules (along the edge, radial inner and outer part) and the scratch
  // sizes: lines of a near rule, lines of any rule, points of any line.
  spectral::Rule near_edge_, near_radial_, near_radial_out_;
  int max_near_lines_ = 0, max_lines_ = 0;
};

}  // namespace capflow::stokes
