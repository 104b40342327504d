// capflow/stokes/operator_call: see operator_call.h.
#include "stokes/operator_call.h"

#include <omp.h>

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <thread>

#include "geometry/element_search.h"
#include "stokes/thread_cap.h"

namespace capflow::stokes {

using Eigen::Matrix3Xd;
using Eigen::Vector3d;

template <Mode M>
OperatorCall<M>::OperatorCall(const BoundaryOperators& ops, const Matrix3Xd& x,
                              const Matrix3Xd* dens, const std::vector<int>* node_targets,
                              const Matrix3Xd* point_targets, Eigen::MatrixXd& out,
                              RowMat* matrix, const NodeExpansion* expansion,
                              const DensityFn* make_density)
    : ops_(ops),
      mesh_(ops.mesh_),
      x_(x),
      dens_(dens),
      node_targets_(node_targets),
      point_targets_(point_targets),
      out_(out),
      matrix_(matrix),
      expansion_(expansion),
      make_density_(make_density),
      nb_(mesh_.nb()),
      ne_(mesh_.ne()),
      nloc_(mesh_.num_local()),
      ntiers_(kSingle ? 3 : 2),
      team_(0),
      jf_(kSingle && ops.opt_.interpolate_jf),
      cheb_(kSingle && !ops.opt_.interpolate_jf),
      // the single layer's near tier ends at single_near_factor sizes, its inner mid tier (2)
      // below single_mid_split, the mid tier (1) beyond
      near_factor_(kSingle ? ops.opt_.single_near_factor : ops.opt_.near_factor),
      split_(kSingle ? ops.opt_.single_mid_split : 0.0) {}

template <Mode M>
OperatorStats OperatorCall<M>::run() {
  check();
  prepare();
  geometry_phase();
  density_phase();
  const PairSumData data = pair_sum_data();
  if constexpr (kAssemble) {
    sums<MatrixAssembly>([&](Scratch& sc, MatrixWorkspace& mw) {
      return MatrixAssembly(data, sc, mw, *matrix_, expansion_);
    });
  } else {
    sums<VectorSums<M>>(
        [&](Scratch& sc, MatrixWorkspace&) { return VectorSums<M>(data, sc, out_); });
  }
  OperatorStats stats;
  stats.targets = ntar_;
  stats.far_pairs = far_pairs_;
  stats.own_pairs = own_pairs_;
  stats.near_pairs = near_pairs_;
  stats.near_elements = near_elements_;
  stats.searches = searches_;
  stats.inner_far_elements = static_cast<long>(inner_.size()) + late_inner_;
  stats.inner_far_late = late_inner_;
  double flops = line_flops_;
  if (shared_lines_)
    flops += single_flops(nb_, static_cast<double>(own_buffers_->own_lines.lines()), 0);
  if (kSingle) stats.flops = flops + 31.0 * static_cast<double>(far_pairs_);
  return stats;
}

// ---- check ------------------------------------------------------------------------------------

template <Mode M>
void OperatorCall<M>::check() {
  if (x_.cols() != nloc_) throw std::invalid_argument("BoundaryOperators: x has wrong size");
  // the density make_density makes: now when interpolate_jf needs it before the phases
  if (make_density_ && jf_) {
    (*make_density_)(made_);
    dens_ = &made_;
    make_density_ = nullptr;
  }
  if (!make_density_ && uses_density(M) && (!dens_ || dens_->cols() != nloc_))
    throw std::invalid_argument("BoundaryOperators: density has wrong size");
  ntar_ = node_targets_ ? static_cast<int>(node_targets_->size())
                        : static_cast<int>(point_targets_->cols());
  if (node_targets_)
    for (int m : *node_targets_)
      if (m < 0 || m >= nloc_) throw std::invalid_argument("BoundaryOperators: bad target index");
  out_.resize(VectorSums<M>::kRows, ntar_);
  if constexpr (kAssemble) {
    // one row block of 3 per target, columns by the expansion
    if (!node_targets_ || !matrix_)
      throw std::invalid_argument("BoundaryOperators: the matrix is assembled at nodes only");
    if (expansion_ && (static_cast<int>(expansion_->column.size()) != nloc_ ||
                       static_cast<int>(expansion_->sign.size()) != nloc_))
      throw std::invalid_argument("BoundaryOperators: the expansion does not cover every node");
    const int ncols = expansion_ ? expansion_->columns : nloc_;
    if (expansion_)
      for (int c : expansion_->column)
        if (c < 0 || c >= ncols)
          throw std::invalid_argument("BoundaryOperators: an expansion column out of range");
    matrix_->setZero(3 * ntar_, 3 * ncols);
  }
}

// ---- prepare ----------------------------------------------------------------------------------

// With interpolate_jf the special rules interpolate g = J f from its nodal values (J = |x_xi x
// x_eta| at the nodes from the differentiation matrix).
template <Mode M>
void OperatorCall<M>::prepare() {
  if (!jf_) return;
  const int nb = nb_, nb2 = nb * nb;
  g_.resize(3, nloc_);
  const Eigen::MatrixXd& D = mesh_.diff();
  for (int e = 0; e < ne_; ++e)
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        Vector3d xs = Vector3d::Zero(), xt = Vector3d::Zero();
        for (int k = 0; k < nb; ++k) {
          xs += D(i, k) * x_.col(e * nb2 + j * nb + k);
          xt += D(j, k) * x_.col(e * nb2 + k * nb + i);
        }
        const int m = e * nb2 + j * nb + i;
        g_.col(m) = xs.cross(xt).norm() * (*dens_).col(m);
      }
}

// ---- geometry ---------------------------------------------------------------------------------

template <Mode M>
void OperatorCall<M>::geometry_phase() {
  esize_.assign(ne_, 0.0);
  bound_.assign(ne_, ElementBounds{});
  // The buffers of a call stay with the calling thread, reused by its next call of this mode
  // (stokes/thread_buffers.h).
  own_buffers_ = &thread_buffers<M>();
  std::vector<ChebElement>& ce = own_buffers_->cheb;
  if (cheb_ && static_cast<int>(ce.size()) < ne_) ce.resize(ne_);
  FarData* const far = own_buffers_->far;  // the calling thread's, shared with the team below
  for (int tier = 0; tier < ntiers_; ++tier) {
    far[tier].nq = static_cast<int>(ops_.far_basis_[tier].w.size());
    far[tier].d.resize(10, ne_ * far[tier].nq * far[tier].nq);
  }
  team_ = team_size();  // this call's threads (stokes/thread_cap.h)
  target_points_.resize(3, ntar_);
  for (int k = 0; k < ntar_; ++k)
    target_points_.col(k) = node_targets_ ? x_.col((*node_targets_)[k]) : point_targets_->col(k);
  // The single layer's inner mid tier (2, the most points) of element e is made up front only
  // where a target of the call may reach it (element_bounds.h): at the NE=6 octant the three far
  // faces never take it. A pair the bound missed makes it when it needs it (need_inner).
  inner_reached_.assign(ne_, 0);
  std::exception_ptr density_error;
  const int nb2 = nb_ * nb_;
#pragma omp parallel num_threads(team_)
  {
    if (make_density_ && omp_get_thread_num() == 0) {
      try {
        (*make_density_)(made_);
      } catch (...) {
        density_error = std::current_exception();
      }
    }
#pragma omp for schedule(dynamic, 1)
    for (int task = 0; task < 2 * ne_; ++task) {
      const int tier = 1 - task / ne_, e = task % ne_;
      far_geometry<M>(mesh_, x_, ops_.far_basis_[tier], e, far[tier],
                      tier == 0 ? &esize_[e] : nullptr);
      if (tier == 1) {
        if (cheb_) chebyshev_element(nb_, 0, 3, ops_.cheb_, x_, nullptr, e * nb2, ce[e]);
      } else {
        bound_[e] = element_bounds(x_, nb_, e);
        if (ntiers_ == 3)
          inner_reached_[e] =
              within_reach(mesh_, x_, e, bound_[e], target_points_, split_ * esize_[e]);
      }
    }
  }
  if (density_error) std::rethrow_exception(density_error);
  if (make_density_) {
    dens_ = &made_;
    if (uses_density(M) && dens_->cols() != nloc_)
      throw std::invalid_argument("BoundaryOperators: density has wrong size");
  }
}

// ---- density ----------------------------------------------------------------------------------

template <Mode M>
void OperatorCall<M>::make_inner(int e) {
  far_data<M>(mesh_, x_, dens_, ops_.far_basis_[2], e, own_buffers_->far[2], nullptr);
  inner_state_[e].store(2, std::memory_order_release);
}

// The inner tier of e for a pair the bound missed: made by the first thread that needs it,
// awaited by the others. True for the thread that made it.
template <Mode M>
bool OperatorCall<M>::need_inner(int e) {
  if (inner_state_[e].load(std::memory_order_acquire) == 2) return false;
  char absent = 0;
  if (inner_state_[e].compare_exchange_strong(absent, 1, std::memory_order_acq_rel)) {
    make_inner(e);
    return true;
  }
  while (inner_state_[e].load(std::memory_order_acquire) != 2) std::this_thread::yield();
  return false;
}

template <Mode M>
void OperatorCall<M>::density_phase() {
  inner_state_.reset(new std::atomic<char>[ne_]);
  inner_.clear();
  for (int e = 0; e < ne_; ++e) {
    inner_state_[e].store(0, std::memory_order_relaxed);
    if (inner_reached_[e]) inner_.push_back(e);
  }
  // The single layer's own lines: stage 1 once per (element, direction, node index) of the
  // targets' own elements (own_lines.h), when every own rule has the same ray nodes.
  shared_lines_ = cheb_ && node_targets_ && ops_.own_.ray_nodes() > 0;
  OwnLines& own_lines = own_buffers_->own_lines;
  const int nb2 = nb_ * nb_;
  if (shared_lines_) {
    own_lines.reset(ne_, nb_, ops_.own_.ray_nodes());
    for (int m : *node_targets_)
      for (int q : mesh_.classes()[mesh_.unique_of()[m]]) {
        const int e = q / nb2, loc = q % nb2;
        own_lines.need(e, 0, loc % nb_);
        own_lines.need(e, 1, loc / nb_);
      }
    own_lines.allocate();
  }
  const int ninner = static_cast<int>(inner_.size());
  const int nslots = shared_lines_ ? own_lines.slots() : 0;
  constexpr int K = uses_density(M) ? 6 : 3;
  FarData* const far = own_buffers_->far;
  std::vector<ChebElement>& ce = own_buffers_->cheb;
#pragma omp parallel num_threads(team_)
  {
#pragma omp for schedule(dynamic, 1)
    for (int task = 0; task < ninner + 2 * ne_; ++task) {
      if (task < ninner) {
        make_inner(inner_[task]);
        continue;
      }
      const int tier = 1 - (task - ninner) / ne_, e = (task - ninner) % ne_;
      far_density<M>(mesh_, dens_, ops_.far_basis_[tier], e, far[tier]);
      if (tier == 1 && cheb_) chebyshev_element(nb_, 3, K, ops_.cheb_, x_, dens_, e * nb2, ce[e]);
    }
#pragma omp for schedule(dynamic, 1)
    for (int slot = 0; slot < nslots; ++slot) own_lines.make(slot, ops_.own_, ce);
  }
}

// ---- sums -------------------------------------------------------------------------------------

template <Mode M>
PairSumData OperatorCall<M>::pair_sum_data() const {
  PairSumData d;
  d.nb = nb_;
  d.K = uses_density(M) ? 6 : 3;
  d.basis = NodalBasis{mesh_.nodes().data(), ops_.prod_w_.data(), mesh_.diff().data()};
  d.own = &ops_.own_;
  d.x = &x_;
  d.density = jf_ ? &g_ : dens_;
  d.cheb = cheb_ ? &own_buffers_->cheb : nullptr;
  d.own_lines = shared_lines_ ? &own_buffers_->own_lines : nullptr;
  d.jf = jf_;
  d.far_basis = ops_.far_basis_;
  return d;
}

// The targets in the order of their expected cost, the dearest first (dynamic scheduling then
// ends with cheap targets instead of one thread finishing a dear one alone): node targets by the
// size of their coincidence class (edge and corner nodes sum 2-4 own rules and more near
// elements). Each target's sum does not depend on the order.
template <Mode M>
std::vector<int> OperatorCall<M>::target_order() const {
  std::vector<int> order(ntar_);
  for (int k = 0; k < ntar_; ++k) order[k] = k;
  if (node_targets_) {
    auto cost = [&](int k) {
      return mesh_.classes()[mesh_.unique_of()[(*node_targets_)[k]]].size();
    };
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cost(a) > cost(b); });
  }
  return order;
}

// The near-singular rule about the nearest point np into sc.near: polar about p*, its radial
// sinh scale per edge h / max |J v| over the rays to the edge's two ends (|J v|^2 is convex
// along the edge), J = [x_s x_t] at p*; then its point bases.
template <Mode M>
void OperatorCall<M>::near_rule(const geometry::NearestPoint& np, Scratch& sc) const {
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
  const RadialOpt ro{&ops_.near_radial_, &ops_.near_radial_out_, ops_.opt_.near_split,
                     ops_.opt_.near_out_panels};
  polar_rule(np.s, np.t, hu, ops_.near_edge_, ops_.near_radial_, sc.near, ro);
  fill_bases(mesh_, ops_.prod_w_, sc.near);
}

template <Mode M>
template <class Visitor, class MakeVisitor>
void OperatorCall<M>::sums(MakeVisitor make_visitor) {
  const std::vector<int> order = target_order();
  long far_pairs = 0, own_pairs = 0, near_pairs = 0, near_elements = 0, searches = 0;
  long late_inner = 0;
  double line_flops = 0;
#pragma omp parallel num_threads(team_) reduction(+ : far_pairs, own_pairs, near_pairs, \
                                                    near_elements, searches, line_flops, late_inner)
  {
    ThreadBuffers& tb = thread_buffers<M>();  // per OpenMP thread, kept across calls
    Scratch& sc = tb.scratch;
    size_scratch(sc, nb_, ops_.max_lines_);
    sc.near.Lc.resize(nb_, ops_.max_near_lines_);
    sc.near.dLc.resize(nb_, ops_.max_near_lines_);
    std::vector<char> own(ne_);
    Visitor v = make_visitor(sc, tb.matrix);
    Counts c;
#pragma omp for schedule(dynamic, 1)
    for (int kk = 0; kk < ntar_; ++kk) sum_target(order[kk], v, sc, own, c);
    far_pairs += c.far_pairs;
    own_pairs += c.own_pairs;
    near_pairs += c.near_pairs;
    near_elements += c.near_elements;
    searches += c.searches;
    late_inner += c.late_inner;
    line_flops += c.line_flops;
  }
  far_pairs_ = far_pairs;
  own_pairs_ = own_pairs;
  near_pairs_ = near_pairs;
  near_elements_ = near_elements;
  searches_ = searches;
  late_inner_ = late_inner;
  line_flops_ = line_flops;
}

// Target k: its own elements (every member of its coincidence class) by their own rules, then
// every other element by its pair rule.
template <Mode M>
template <class Visitor>
void OperatorCall<M>::sum_target(int k, Visitor& v, Scratch& sc, std::vector<char>& own,
                                 Counts& c) {
  const int nb2 = nb_ * nb_;
  const Vector3d x0 = target_points_.col(k);
  Vector3d u0 = Vector3d::Zero();
  if (M == Mode::Double && node_targets_) u0 = dens_->col((*node_targets_)[k]);
  v.begin(k, x0, u0);
  std::fill(own.begin(), own.end(), 0);
  if (node_targets_) {
    const int m = (*node_targets_)[k];
    for (int q : mesh_.classes()[mesh_.unique_of()[m]]) {
      const int e = q / nb2, loc = q % nb2;
      own[e] = 1;
      const LineRule& r = ops_.own_.rule(loc);
      c.line_flops += v.own(e, loc, r, ops_.own_.symmetry(loc));
      c.own_pairs += r.np();
    }
  }
  const QuadratureOptions& opt = ops_.opt_;
  FarData* const far = own_buffers_->far;
  for (int e = 0; e < ne_; ++e) {
    if (own[e]) continue;
    const PairThresholds th{near_factor_ * esize_[e], split_ * esize_[e],
                            opt.mid_factor * esize_[e]};
    const PairRule p = choose_pair_rule(mesh_, x_, e, bound_[e], x0, th);
    c.searches += p.searched;
    if (p.near) {
      ++c.near_elements;
      near_rule(p.np, sc);
      c.line_flops += v.near(e);
      c.near_pairs += sc.near.np();
    } else {
      if (p.tier == 2 && need_inner(e)) ++c.late_inner;
      const FarData& fd = far[p.tier];
      v.far(fd, e, p.tier);
      c.far_pairs += fd.nq * fd.nq;
    }
  }
  v.finish(k, node_targets_ ? (*node_targets_)[k] : -1);
}

template class OperatorCall<Mode::Single>;
template class OperatorCall<Mode::SingleNormal>;
template class OperatorCall<Mode::Double>;
template class OperatorCall<Mode::DoubleNormal>;
template class OperatorCall<Mode::DoubleMatrix>;

}  // namespace capflow::stokes
