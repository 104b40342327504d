#include "stokes/boundary_integral.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <memory>
#include <stdexcept>
#include <thread>

#include "geometry/element_search.h"
#include "geometry/surface.h"
#include "spectral/spectral.h"
#include "stokes/element_bounds.h"
#include "stokes/line_sums.h"
#include "stokes/matrix_sums.h"
#include "stokes/thread_buffers.h"
#include "stokes/thread_cap.h"

namespace capflow::stokes {

using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {
// The single layer's counted flops (OperatorStats::flops): stage 1 of `lines` lines, stage 2
// and the kernel at `points` points.
double single_flops(int nb, double lines, double points) {
  const auto pad8 = [](int n) { return (n + 7) & ~7; };
  return lines * (2.0 * nb * (pad8(6 * nb) + pad8(3 * nb)) + 3.0 * nb) +
         points * (28.0 * nb + 36.0);
}
double single_rule_flops(int nb, const LineRule& r) {
  return single_flops(nb, r.nl(), r.np());
}
}  // namespace

QuadratureOptions resolve_defaults(const geometry::Mesh& mesh, QuadratureOptions opt) {
  const int nb = mesh.nb();
  if (nb > kMaxNb) throw std::invalid_argument("BoundaryOperators: nb too large");
  // Far order: a capsule's traction carries its full degree nb-1 (it comes from second
  // derivatives of the geometry), so f J is of degree ~3(nb-1) on an element; Gauss with
  // (3nb+19)/2 points integrates that exactly with ~10 points to spare for the kernel. nb + 3
  // (enough for the smooth densities of the sphere identities) left a quarter of the fig. 2b
  // steady-state volume leak and two thirds of the NH Ca=0.4 one at t=17.4
  // (benchmarks/capsule/volume_flux --far-scale; docs/validation.md, 9.2 "The far Gauss order").
  if (opt.nq_far <= 0) opt.nq_far = (3 * nb + 19) / 2;
  // Mid order: 2 nb + 4 left 1e-4 (relative) in SL[f] at the strongly deformed NH Ca=0.4 state
  // (NE=14 NB=10, t=17.4; benchmarks/capsule/quadrature_study), 3 nb + 2 leaves 3e-5.
  if (opt.nq_mid <= 0) opt.nq_mid = 3 * nb + 2;
  // The single layer's near tier can end at 0.1 sizes (0.2 for the double layer) with 4 nb + 4
  // Gauss points beyond: the same accuracy on the sphere identities and the deformed shapes of
  // tests/stokes at 11-24 % less time per call (docs/performance.md).
  if (opt.single_nq_mid <= 0) opt.single_nq_mid = 4 * nb + 4;
  if (!(opt.single_near_factor > 0.0 && opt.near_factor > 0.0 && opt.single_mid_split >= 0.0))
    throw std::invalid_argument("BoundaryOperators: near factors must be positive");
  // Elongated elements (NE=14 rows: 30 x 90 degrees) stretch the sinh-mapped edge coordinate
  // over a longer physical length; with the square-element orders their next-to-edge nodes miss
  // INT T.n = -4 pi I by 8e-8 at NB=12, with these 2.4e-9 (tests/stokes, StokesSphere).
  double aspect = 1.0;
  for (const geometry::Patch& p : mesh.patches()) {
    const double da = std::abs(p.a1 - p.a0), db = std::abs(p.b1 - p.b0);
    aspect = std::max(aspect, std::max(da, db) / std::min(da, db));
  }
  const bool elongated = aspect > 2.05;
  if (opt.n_edge <= 0) opt.n_edge = elongated ? 3 * nb : 2 * nb;
  if (opt.n_radial_inner < 0) opt.n_radial_inner = nb + 2;
  if (opt.n_radial <= 0) opt.n_radial = opt.n_radial_inner > 0 ? nb : nb + 4;
  if (opt.n_edge_near <= 0) opt.n_edge_near = elongated ? 2 * nb : nb + 6;
  if (opt.n_radial_near <= 0) opt.n_radial_near = nb;
  if (opt.n_radial_near_out <= 0) opt.n_radial_near_out = std::max(4, nb - 2);
  if (opt.near_out_panels < 1 || opt.near_out_panels > 8)
    throw std::invalid_argument("BoundaryOperators: near_out_panels must be in 1..8");
  if (!(opt.own_edge_slope >= 0.0))
    throw std::invalid_argument("BoundaryOperators: own_edge_slope must be >= 0");
  if (opt.n_radial_inner > 0 &&
      !(opt.own_split > 0.0 && opt.own_split < 1.0 && opt.own_grading > 0.0))
    throw std::invalid_argument("BoundaryOperators: own_split must be in (0, 1), own_grading > 0");
  if (opt.n_edge > kMaxEdge || opt.n_edge_near > kMaxEdge)
    throw std::invalid_argument("BoundaryOperators: n_edge / n_edge_near > 256");
  return opt;
}

BoundaryOperators::BoundaryOperators(const geometry::Mesh& mesh, QuadratureOptions options)
    : mesh_(mesh),
      opt_(resolve_defaults(mesh, options)),
      prod_w_(spectral::product_weights(mesh.nodes())),
      cheb_(spectral::chebyshev_matrix(mesh.nodes())),
      own_(mesh, opt_, prod_w_) {
  const int nq[3] = {opt_.nq_far, opt_.nq_mid, opt_.single_nq_mid};
  for (int tier = 0; tier < 3; ++tier) far_basis_[tier] = far_basis(mesh.nodes(), nq[tier]);
  near_edge_ = spectral::gauss_legendre(opt_.n_edge_near);
  near_radial_ = spectral::gauss_legendre(opt_.n_radial_near);
  near_radial_out_ = spectral::gauss_legendre(opt_.n_radial_near_out);
  // near rule: 4 edges x n_radial_near x panels (asinh(1/hu) <= asinh(1e14) < 6 * 6) lines
  max_near_lines_ = 4 * (opt_.n_radial_near * 6 + opt_.n_radial_near_out * opt_.near_out_panels);
  max_lines_ = std::max(max_near_lines_, own_.max_lines());
}
template <BoundaryOperators::Mode M>
OperatorStats BoundaryOperators::apply(const Matrix3Xd& x, const Matrix3Xd* dens,
                                       const std::vector<int>* node_targets,
                                       const Matrix3Xd* point_targets, MatrixXd& out,
                                       RowMat* matrix, const NodeExpansion* expansion,
                                       const DensityFn* make_density) const {
  const geometry::Mesh& mesh = mesh_;
  const int nb = mesh.nb(), nb2 = nb * nb, ne = mesh.ne();
  const int nloc = mesh.num_local();
  if (x.cols() != nloc) throw std::invalid_argument("BoundaryOperators: x has wrong size");
  // the density make_density makes (during phase 1; interpolate_jf needs it before)
  Matrix3Xd made;
  const bool jf = M == Mode::Single && opt_.interpolate_jf;
  if (make_density && jf) {
    (*make_density)(made);
    dens = &made;
    make_density = nullptr;
  }
  const auto check_density = [&] {
    if (uses_density(M) && (!dens || dens->cols() != nloc))
      throw std::invalid_argument("BoundaryOperators: density has wrong size");
  };
  if (!make_density) check_density();
  const int ntar = node_targets ? static_cast<int>(node_targets->size())
                                : static_cast<int>(point_targets->cols());
  if (node_targets)
    for (int m : *node_targets)
      if (m < 0 || m >= nloc) throw std::invalid_argument("BoundaryOperators: bad target index");
  constexpr int acc_rows = (M == Mode::DoubleNormal) ? 9 : 3;
  out.resize(acc_rows, ntar);
  // the assembled double layer: one row block of 3 per target, columns by the expansion
  constexpr bool assemble = M == Mode::DoubleMatrix;
  if (assemble) {
    if (!node_targets || !matrix)
      throw std::invalid_argument("BoundaryOperators: the matrix is assembled at nodes only");
    if (expansion && (static_cast<int>(expansion->column.size()) != nloc ||
                      static_cast<int>(expansion->sign.size()) != nloc))
      throw std::invalid_argument("BoundaryOperators: the expansion does not cover every node");
    const int ncols = expansion ? expansion->columns : nloc;
    if (expansion)
      for (int c : expansion->column)
        if (c < 0 || c >= ncols)
          throw std::invalid_argument("BoundaryOperators: an expansion column out of range");
    matrix->setZero(3 * ntar, 3 * ncols);
  }
  constexpr int K = uses_density(M) ? 6 : 3;

  // ---- far-field data at Gauss points (per call: depends on the geometry) ----
  // Two orders: nq_far for elements at distance >= mid_factor * size, nq_mid between
  // near_factor * size and that (the single layer: single_nq_mid from single_near_factor).
  const bool single = M == Mode::Single;
  const double near_factor = single ? opt_.single_near_factor : opt_.near_factor;
  // the single layer's inner mid tier (2) below single_mid_split, the mid tier (1) beyond
  const double split = single ? opt_.single_mid_split : 0.0;
  // Single layer with interpolate_jf: the special rules interpolate g = J f from its nodal
  // values (J = |x_xi x x_eta| at the nodes from the differentiation matrix).
  Matrix3Xd g;
  if (jf) {
    g.resize(3, nloc);
    const MatrixXd& D = mesh.diff();
    for (int e = 0; e < ne; ++e)
      for (int j = 0; j < nb; ++j)
        for (int i = 0; i < nb; ++i) {
          Vector3d xs = Vector3d::Zero(), xt = Vector3d::Zero();
          for (int k = 0; k < nb; ++k) {
            xs += D(i, k) * x.col(e * nb2 + j * nb + k);
            xt += D(j, k) * x.col(e * nb2 + k * nb + i);
          }
          const int m = e * nb2 + j * nb + i;
          g.col(m) = xs.cross(xt).norm() * (*dens).col(m);
        }
  }
  std::vector<double> esize(ne);
  std::vector<ElementBounds> bound(ne);
  // The buffers of a call stay with the calling thread, reused by its next call of this mode
  // (stokes/thread_buffers.h).
  ThreadBuffers& own_buffers = thread_buffers<M>();
  // single layer: the elements' data in Chebyshev coefficients along the rule lines
  const bool cheb = M == Mode::Single && !jf;
  std::vector<ChebElement>& ce = own_buffers.cheb;
  if (cheb && static_cast<int>(ce.size()) < ne) ce.resize(ne);
  FarData* const far = own_buffers.far;  // the calling thread's, shared with the team below
  const int ntiers = single ? 3 : 2;
  for (int tier = 0; tier < ntiers; ++tier) {
    far[tier].nq = static_cast<int>(far_basis_[tier].w.size());
    far[tier].d.resize(10, ne * far[tier].nq * far[tier].nq);
  }
  const int team = team_size();  // this call's threads (stokes/thread_cap.h)
  Matrix3Xd target_points(3, ntar);
  for (int k = 0; k < ntar; ++k)
    target_points.col(k) = node_targets ? x.col((*node_targets)[k]) : point_targets->col(k);
  // The single layer's inner mid tier (2, the most points) of element e is made up front only
  // where a target of the call may reach it (element_bounds.h): at the NE=6 octant the three
  // far faces never take it. A pair the bound missed makes it when it needs it (make_inner).
  std::vector<char> inner_reached(ne, 0);
  // Phase 1, what needs only x: one task per (tier, element) of the tiers 1 and 0 (the far data
  // is ~10 % of a call, serial it left a core idle), the dearer tier first: the far tier's
  // surface rows; the Chebyshev element data of x with tier 1; with tier 0 the element's size,
  // its bounds and whether a target reaches its inner tier. With make_density, the team's first
  // thread computes the density meanwhile and then joins the tasks left.
  std::exception_ptr density_error;
#pragma omp parallel num_threads(team)
  {
    if (make_density && omp_get_thread_num() == 0) {
      try {
        (*make_density)(made);
      } catch (...) {
        density_error = std::current_exception();
      }
    }
#pragma omp for schedule(dynamic, 1)
    for (int task = 0; task < 2 * ne; ++task) {
      const int tier = 1 - task / ne, e = task % ne;
      far_geometry<M>(mesh, x, far_basis_[tier], e, far[tier], tier == 0 ? &esize[e] : nullptr);
      if (tier == 1) {
        if (cheb) chebyshev_element(nb, 0, 3, cheb_, x, nullptr, e * nb2, ce[e]);
      } else {
        bound[e] = element_bounds(x, nb, e);
        if (ntiers == 3)
          inner_reached[e] = within_reach(mesh, x, e, bound[e], target_points, split * esize[e]);
      }
    }
  }
  if (density_error) std::rethrow_exception(density_error);
  if (make_density) {
    dens = &made;
    check_density();
  }
  const Matrix3Xd* sdens = jf ? &g : dens;
  // Per element, its inner tier's data: 0 absent, 1 being made, 2 made.
  std::unique_ptr<std::atomic<char>[]> inner_state(new std::atomic<char>[ne]);
  std::vector<int> inner;  // the elements whose inner tier phase 2 makes
  for (int e = 0; e < ne; ++e) {
    inner_state[e].store(0, std::memory_order_relaxed);
    if (inner_reached[e]) inner.push_back(e);
  }
  const auto make_inner = [&](int e) {
    far_data<M>(mesh, x, dens, far_basis_[2], e, far[2], nullptr);
    inner_state[e].store(2, std::memory_order_release);
  };
  // The single layer's own lines: stage 1 once per (element, direction, node index) of the
  // targets' own elements (own_lines.h), when every own rule has the same ray nodes.
  const bool shared_lines = cheb && node_targets && own_.ray_nodes() > 0;
  OwnLines& own_lines = own_buffers.own_lines;
  if (shared_lines) {
    own_lines.reset(ne, nb, own_.ray_nodes());
    for (int m : *node_targets)
      for (int q : mesh.classes()[mesh.unique_of()[m]]) {
        const int e = q / nb2, loc = q % nb2;
        own_lines.need(e, 0, loc % nb);
        own_lines.need(e, 1, loc / nb);
      }
    own_lines.allocate();
  }
  // Phase 2, what needs the density: the reached inner tiers (the dearest tasks first) and the
  // density rows of the tiers 1 and 0 (with the Chebyshev element data of the density), then
  // the own lines' slots, which read that Chebyshev data.
  const int ninner = static_cast<int>(inner.size());
  const int nslots = shared_lines ? own_lines.slots() : 0;
#pragma omp parallel num_threads(team)
  {
#pragma omp for schedule(dynamic, 1)
    for (int task = 0; task < ninner + 2 * ne; ++task) {
      if (task < ninner) {
        make_inner(inner[task]);
        continue;
      }
      const int tier = 1 - (task - ninner) / ne, e = (task - ninner) % ne;
      far_density<M>(mesh, dens, far_basis_[tier], e, far[tier]);
      if (tier == 1 && cheb) chebyshev_element(nb, 3, K, cheb_, x, dens, e * nb2, ce[e]);
    }
#pragma omp for schedule(dynamic, 1)
    for (int slot = 0; slot < nslots; ++slot) own_lines.make(slot, own_, ce);
  }
  // the inner tier of e for a pair the bound missed: made by the first thread that needs it,
  // awaited by the others
  const auto need_inner = [&](int e) {
    if (inner_state[e].load(std::memory_order_acquire) == 2) return false;
    char absent = 0;
    if (inner_state[e].compare_exchange_strong(absent, 1, std::memory_order_acq_rel)) {
      make_inner(e);
      return true;
    }
    while (inner_state[e].load(std::memory_order_acquire) != 2) std::this_thread::yield();
    return false;
  };

  const int max_near_lines = max_near_lines_, max_lines = max_lines_;
  const NodalBasis basis{mesh.nodes().data(), prod_w_.data(), mesh.diff().data()};
  // The targets in the order of their expected cost, the dearest first (dynamic scheduling then
  // ends with cheap targets instead of one thread finishing a dear one alone): node targets by
  // the size of their coincidence class (edge and corner nodes sum 2-4 own rules and more near
  // elements). Each target's sum does not depend on the order.
  std::vector<int> order(ntar);
  for (int k = 0; k < ntar; ++k) order[k] = k;
  if (node_targets) {
    auto cost = [&](int k) { return mesh.classes()[mesh.unique_of()[(*node_targets)[k]]].size(); };
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cost(a) > cost(b); });
  }

  long far_pairs = 0, own_pairs = 0, near_pairs = 0, near_elements = 0, searches = 0;
  long late_inner = 0;
  double line_flops = 0;
#pragma omp parallel num_threads(team) reduction(+ : far_pairs, own_pairs, near_pairs, \
                                                   near_elements, searches, line_flops, late_inner)
  {
    Scratch& sc = thread_buffers<M>().scratch;  // per OpenMP thread, kept across calls
    size_scratch(sc, nb, max_lines);
    sc.near.Lc.resize(nb, max_near_lines);
    sc.near.dLc.resize(nb, max_near_lines);
    std::vector<char> own(ne);
    MatrixWorkspace& mw = thread_buffers<M>().matrix;
    // assemble: the element's kernel sums E (node in the rule's orientation: perm) added to the
    // row block of target k, and the total subtracted at the target's own column
    const auto sym3 = [](const double* s, int i, int j) {
      static constexpr int idx[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
      return s[idx[i][j]];
    };
    const auto place = [&](int node, const double* s, double factor, int k) {
      const int col = expansion ? expansion->column[node] : node;
      for (int j = 0; j < 3; ++j) {
        const double sg = factor * (expansion ? expansion->sign[node][j] : 1.0);
        for (int i = 0; i < 3; ++i) (*matrix)(3 * k + i, 3 * col + j) += sg * sym3(s, i, j);
      }
    };
    const auto scatter = [&](const MatrixXd& E, int base, const int* perm, int k) {
      double s[6];
      for (int n = 0; n < nb2; ++n) {
        for (int c = 0; c < 6; ++c) s[c] = E(n, c);
        place(base + (perm ? perm[n] : n), s, 1.0, k);
      }
    };
    const auto scatter_total = [&](const double* t, int node, int k) { place(node, t, -1.0, k); };
    (void)scatter;
    (void)scatter_total;

#pragma omp for schedule(dynamic, 1)
    for (int kk = 0; kk < ntar; ++kk) {
      const int k = order[kk];
      double acc[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
      double total[6] = {0, 0, 0, 0, 0, 0};  // assemble: the kernel's sum (the -u(x0) term)
      const Vector3d x0 = target_points.col(k);
      Vector3d u0 = Vector3d::Zero();
      std::fill(own.begin(), own.end(), 0);
      if (node_targets) {
        const int m = (*node_targets)[k];
        if (M == Mode::Double) u0 = dens->col(m);
        // own elements: every member of the coincidence class
        for (int q : mesh.classes()[mesh.unique_of()[m]]) {
          const int e = q / nb2, loc = q % nb2;
          own[e] = 1;
          const LineRule& r = own_.rule(loc);
          const int sym = own_.symmetry(loc);
          const double sign = OwnRules::sign(sym);
          if (shared_lines) {
            sc.rows.resize(r.nl());
            for (int l = 0; l < r.nl(); ++l)
              sc.rows[l] = own_lines.rows(e, OwnRules::element_line(r, l, sym), loc % nb, loc / nb);
            single_rows_sum(nb, r, sc.rows.data(), x0, acc);
            own_pairs += r.np();
            line_flops += single_flops(nb, 0, r.np());
            continue;
          }
          if (cheb)
            load_chebyshev(nb, K, ce[e], sym, sc);
          else
            load_element(nb, K, x, sdens, e * nb2, own_.permutation(sym), sc);
          if constexpr (assemble) {
            line_matrix(nb, r, basis, sign, x0, sc, mw, mw.E, total);
            scatter(mw.E, e * nb2, own_.permutation(sym), k);
          } else if (jf) {
            line_sum_jf(nb, r, basis, x0, sc, acc);
          } else {
            line_sum<M>(nb, K, r, basis, sign, x0, u0, sc, acc);
          }
          own_pairs += r.np();
          if (M == Mode::Single) line_flops += single_rule_flops(nb, r);
        }
      }
      for (int e = 0; e < ne; ++e) {
        if (own[e]) continue;
        bool near = false;
        int tier = 0;  // far order: 0 nq_far, 1 nq_mid, 2 single_nq_mid
        geometry::NearestPoint np;
        const double crit = near_factor * esize[e];
        const double crit_mid = opt_.mid_factor * esize[e];
        if ((x0 - bound[e].centre).norm() - bound[e].radius < crit_mid) {
          // The distance h of x0 to the element lies in [d - cell, d], d the distance to the
          // nearest node: the nearest point is searched only when h may be below crit (the
          // near rule needs it) or the interval straddles a tier's threshold.
          int best = 0;
          const double d = geometry::nearest_node(mesh, x, e, x0, &best), lo = d - bound[e].cell;
          const double thresholds[2] = {split * esize[e], crit_mid};
          bool decided = lo >= crit;
          for (double th : thresholds) decided = decided && (th <= 0.0 || lo >= th || d < th);
          if (decided) {
            tier = d < crit_mid ? (d < split * esize[e] ? 2 : 1) : 0;
          } else {
            np = geometry::nearest_point(mesh, x, e, x0, best);
            ++searches;
            near = np.h < crit;
            tier = np.h < crit_mid ? (np.h < split * esize[e] ? 2 : 1) : 0;
          }
        }
        if (near) {
          ++near_elements;
          // radial sinh scale per edge: h / max |J v| over the rays to the edge's two ends
          // (|J v|^2 is convex along the edge), J = [x_s x_t] at p*.
          double hu[4];
          const double ends[4][2][2] = {
              {{-1, -1}, {-1, 1}}, {{1, -1}, {1, 1}}, {{-1, -1}, {1, -1}}, {{-1, 1}, {1, 1}}};
          for (int ei = 0; ei < 4; ++ei) {
            double jv = 0;
            for (int k2 = 0; k2 < 2; ++k2)
              jv = std::max(
                  jv, (np.xs * (ends[ei][k2][0] - np.s) + np.xt * (ends[ei][k2][1] - np.t)).norm());
            hu[ei] = np.h / jv;
            if (hu[ei] < 1e-13) hu[ei] = 0.0;
          }
          const RadialOpt ro{&near_radial_, &near_radial_out_, opt_.near_split,
                             opt_.near_out_panels};
          polar_rule(np.s, np.t, hu, near_edge_, near_radial_, sc.near, ro);
          // the single layer evaluates the near rule's point bases line by line
          fill_bases(mesh, prod_w_, sc.near);
          if (cheb) {
            single_sum(nb, sc.near, ce[e], x0, sc, acc);
          } else {
            load_element(nb, K, x, sdens, e * nb2, nullptr, sc);
            if constexpr (assemble) {
              line_matrix(nb, sc.near, basis, 1.0, x0, sc, mw, mw.E, total);
              scatter(mw.E, e * nb2, nullptr, k);
            } else if (jf) {
              line_sum_jf(nb, sc.near, basis, x0, sc, acc);
            } else {
              line_sum<M>(nb, K, sc.near, basis, 1.0, x0, u0, sc, acc);
            }
          }
          near_pairs += sc.near.np();
          if (M == Mode::Single) line_flops += single_rule_flops(nb, sc.near);
        } else {
          if (tier == 2 && need_inner(e)) ++late_inner;
          const FarData& fd = far[tier];
          const int nqe = fd.nq * fd.nq;
          if constexpr (assemble) {
            far_matrix(fd, e * nqe, far_basis_[tier].I, x0, mw, mw.E, total);
            scatter(mw.E, e * nb2, nullptr, k);
          } else {
            far_sum<M>(fd, e * nqe, (e + 1) * nqe, x0, u0, acc);
          }
          far_pairs += nqe;
        }
      }
      if constexpr (assemble)
        scatter_total(total, (*node_targets)[k], k);
      else
        for (int r = 0; r < acc_rows; ++r) out(r, k) = acc[r];
    }
  }
  OperatorStats stats;
  stats.targets = ntar;
  stats.far_pairs = far_pairs;
  stats.own_pairs = own_pairs;
  stats.near_pairs = near_pairs;
  stats.near_elements = near_elements;
  stats.searches = searches;
  stats.inner_far_elements = ninner + late_inner;
  stats.inner_far_late = late_inner;
  if (shared_lines) line_flops += single_flops(nb, static_cast<double>(own_lines.lines()), 0);
  if (M == Mode::Single) stats.flops = line_flops + 31.0 * static_cast<double>(far_pairs);
  return stats;
}

namespace {
std::vector<int> class_representatives(const geometry::Mesh& mesh) {
  std::vector<int> reps;
  reps.reserve(mesh.num_unique());
  for (const auto& c : mesh.classes()) reps.push_back(c.front());
  return reps;
}
Matrix3Xd scatter_classes(const geometry::Mesh& mesh, const MatrixXd& v) {
  Matrix3Xd out(3, mesh.num_local());
  const auto& cls = mesh.classes();
  for (size_t c = 0; c < cls.size(); ++c)
    for (int m : cls[c]) out.col(m) = v.col(static_cast<int>(c));
  return out;
}
void keep(OperatorStats* to, const OperatorStats& s) {
  if (to) *to = s;
}
}  // namespace

Matrix3Xd BoundaryOperators::single_layer(const Matrix3Xd& x, const Matrix3Xd& f,
                                          OperatorStats* stats) const {
  const std::vector<int> reps = class_representatives(mesh_);
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, &f, &reps, nullptr, v));
  return scatter_classes(mesh_, v);
}

void BoundaryOperators::single_layer(const Matrix3Xd& x, const Matrix3Xd& f,
                                     const std::vector<int>& targets, Matrix3Xd& out,
                                     OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, &f, &targets, nullptr, v));
  out = v;
}

void BoundaryOperators::single_layer(const Matrix3Xd& x, const DensityFn& density,
                                     const std::vector<int>& targets, Matrix3Xd& out,
                                     OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, nullptr, &targets, nullptr, v, nullptr, nullptr, &density));
  out = v;
}

Matrix3Xd BoundaryOperators::single_layer_at(const Matrix3Xd& x, const Matrix3Xd& f,
                                             const Matrix3Xd& points, OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Single>(x, &f, nullptr, &points, v));
  return v;
}

Matrix3Xd BoundaryOperators::double_layer(const Matrix3Xd& x, const Matrix3Xd& u,
                                          OperatorStats* stats) const {
  const std::vector<int> reps = class_representatives(mesh_);
  MatrixXd v;
  keep(stats, apply<Mode::Double>(x, &u, &reps, nullptr, v));
  return scatter_classes(mesh_, v);
}

void BoundaryOperators::double_layer(const Matrix3Xd& x, const Matrix3Xd& u,
                                     const std::vector<int>& targets, Matrix3Xd& out,
                                     OperatorStats* stats) const {
  MatrixXd v;
  keep(stats, apply<Mode::Double>(x, &u, &targets, nullptr, v));
  out = v;
}

Matrix3Xd BoundaryOperators::single_layer_normal(const Matrix3Xd& x,
                                                 const std::vector<int>& targets) const {
  MatrixXd v;
  apply<Mode::SingleNormal>(x, nullptr, &targets, nullptr, v);
  return v;
}

RowMat BoundaryOperators::double_layer_matrix(const Matrix3Xd& x, const std::vector<int>& targets,
                                              const NodeExpansion* expansion,
                                              OperatorStats* stats) const {
  MatrixXd unused;
  RowMat a;
  keep(stats, apply<Mode::DoubleMatrix>(x, nullptr, &targets, nullptr, unused, &a, expansion));
  return a;
}

MatrixXd BoundaryOperators::double_layer_normal(const Matrix3Xd& x,
                                                const std::vector<int>& targets) const {
  MatrixXd v;
  apply<Mode::DoubleNormal>(x, nullptr, &targets, nullptr, v);
  return v;
}

Matrix3Xd BoundaryOperators::single_layer_gauss(const geometry::Mesh& mesh, const Matrix3Xd& x,
                                                const Matrix3Xd& f, const Matrix3Xd& points,
                                                int nq) {
  const geometry::QuadratureSurface qs = geometry::sample_gauss(mesh, x, nq);
  const MatrixXd fq = geometry::to_gauss(mesh, f, qs.interp);
  Matrix3Xd out(3, points.cols());
#pragma omp parallel for schedule(static) num_threads(team_size())
  for (int k = 0; k < points.cols(); ++k) {
    Vector3d acc = Vector3d::Zero();
    const Vector3d x0 = points.col(k);
    for (int q = 0; q < qs.x.cols(); ++q) {
      const Vector3d r = qs.x.col(q) - x0;
      const double ir = 1.0 / r.norm();
      const Vector3d fv = fq.col(q);
      acc += qs.w[q] * (ir * fv + (ir * ir * ir * r.dot(fv)) * r);
    }
    out.col(k) = acc;
  }
  return out;
}

QuadratureOptions scale_orders(const QuadratureOptions& resolved, const OrderScales& k) {
  if (resolved.nq_far <= 0 || resolved.n_edge <= 0 || resolved.n_edge_near <= 0)
    throw std::invalid_argument(
        "scale_orders: options must be resolved (BoundaryOperators::options())");
  if (!(k.far > 0 && k.own > 0 && k.near > 0 && k.mid >= 0))
    throw std::invalid_argument("scale_orders: factors must be positive");
  QuadratureOptions q = resolved;
  auto up = [](int& n, double f) { n = std::max(2, static_cast<int>(std::lround(n * f))); };
  up(q.nq_far, k.far);
  up(q.nq_mid, k.mid > 0 ? k.mid : k.far);
  up(q.single_nq_mid, k.mid > 0 ? k.mid : k.far);
  up(q.n_edge, k.own);
  if (q.own_edge_base > 0.0) {
    q.own_edge_base *= k.own;
    q.own_edge_slope *= k.own;
  }
  up(q.n_radial, k.own);
  if (q.n_radial_inner > 0) up(q.n_radial_inner, k.own);
  up(q.n_edge_near, k.near);
  up(q.n_radial_near, k.near);
  up(q.n_radial_near_out, k.near);
  return q;
}

}  // namespace capflow::stokes
