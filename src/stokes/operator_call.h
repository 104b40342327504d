// capflow/stokes/operator_call: one application of the boundary operators
// (BoundaryOperators::apply), phase by phase:
//   check     the arguments; the result sized (the assembled matrix zeroed)
//   prepare   the single layer's J f at the nodes (QuadratureOptions::interpolate_jf)
//   geometry  what needs only x, one task per (tier, element) of the far tiers 1 and 0, the dearer
//             first: the far tiers' surface rows, the Chebyshev data of x (tier 1), the element's
//             size, bounds (stokes/element_bounds.h) and whether a target reaches its inner tier
//             (tier 0); with a density made during the call, the team's first thread makes it
//             meanwhile and then joins the tasks left (the far data is ~10 % of a call: serial, it
//             left a core idle)
//   density   what needs the density: the reached inner tiers (the dearest tasks first), the
//             density rows of the tiers 1 and 0 (and its Chebyshev data), then the own lines'
//             slots (stokes/own_lines.h), which read that Chebyshev data
//   sums      per target, the dearest first: its own elements by their own rules, every other
//             element by its pair rule (stokes/pair_rule.h: near, or a far tier), each pair summed
//             by the call's visitor (stokes/pair_sums.h: a vector result, or the assembled matrix)
// Internal to the stokes module.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <memory>
#include <vector>

#include "stokes/boundary_integral.h"
#include "stokes/element_bounds.h"
#include "stokes/far_field.h"
#include "stokes/line_sums.h"
#include "stokes/pair_rule.h"
#include "stokes/pair_sums.h"
#include "stokes/thread_buffers.h"

namespace capflow::stokes {

template <Mode M>
class OperatorCall {
 public:
  using DensityFn = BoundaryOperators::DensityFn;

  OperatorCall(const BoundaryOperators& ops, const Eigen::Matrix3Xd& x,
               const Eigen::Matrix3Xd* dens, const std::vector<int>* node_targets,
               const Eigen::Matrix3Xd* point_targets, Eigen::MatrixXd& out, RowMat* matrix,
               const NodeExpansion* expansion, const DensityFn* make_density);

  OperatorStats run();

 private:
  static constexpr bool kAssemble = M == Mode::DoubleMatrix;
  static constexpr bool kSingle = M == Mode::Single;

  // A thread's counts of the per-target sums.
  struct Counts {
    long far_pairs = 0, own_pairs = 0, near_pairs = 0, near_elements = 0, searches = 0;
    long late_inner = 0;
    double line_flops = 0;
  };

  void check();
  void prepare();
  void geometry_phase();
  void density_phase();
  template <class Visitor, class MakeVisitor>
  void sums(MakeVisitor make_visitor);
  template <class Visitor>
  void sum_target(int k, Visitor& v, Scratch& sc, std::vector<char>& own, Counts& c);
  void near_rule(const geometry::NearestPoint& np, Scratch& sc) const;
  bool need_inner(int e);
  void make_inner(int e);
  std::vector<int> target_order() const;
  PairSumData pair_sum_data() const;

  // the operators and the arguments
  const BoundaryOperators& ops_;
  const geometry::Mesh& mesh_;
  const Eigen::Matrix3Xd& x_;
  const Eigen::Matrix3Xd* dens_;
  const std::vector<int>* node_targets_;
  const Eigen::Matrix3Xd* point_targets_;
  Eigen::MatrixXd& out_;
  RowMat* matrix_;
  const NodeExpansion* expansion_;
  const DensityFn* make_density_;
  // what the phases make
  int nb_, ne_, nloc_, ntar_ = 0, ntiers_, team_;
  bool jf_, cheb_, shared_lines_ = false;
  double near_factor_, split_;
  Eigen::Matrix3Xd made_;  // the density make_density makes
  Eigen::Matrix3Xd g_;     // J f at the nodes (jf)
  Eigen::Matrix3Xd target_points_;
  std::vector<double> esize_;
  std::vector<ElementBounds> bound_;
  std::vector<char> inner_reached_;
  std::vector<int> inner_;  // the elements whose inner tier the density phase makes
  std::unique_ptr<std::atomic<char>[]> inner_state_;  // per element: 0 absent, 1 being made, 2 made
  ThreadBuffers* own_buffers_ = nullptr;  // the calling thread's
  // the counts (OperatorStats)
  long far_pairs_ = 0, own_pairs_ = 0, near_pairs_ = 0, near_elements_ = 0, searches_ = 0;
  long late_inner_ = 0;
  double line_flops_ = 0;
};

}  // namespace capflow::stokes
