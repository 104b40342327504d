// capflow/capsule/continuation: a branch of steady states followed in Ca by pseudo-arclength
// continuation (Keller; e.g. Allgower & Georg, "Numerical Continuation Methods", ch. 2).
//
// Points of the branch are (y, Ca), y the state (node positions, any layout). Distances use
//     <a, b> = a.y . b.y / n + a.ca b.ca       (n = the length of y)
// so that a change of shape counts by its root-mean-square node displacement and a change of Ca
// by itself. From the last two points p0, p1 the secant tangent t = (p1 - p0)/|p1 - p0| predicts
// p1 + ds t; the corrector (a Newton solve, supplied by the caller) finds the steady state on the
// hyperplane through the prediction normal to t: <t, p - prediction> = 0. Ca is an unknown there,
// so the branch is followed through a fold (a largest or smallest Ca of the branch, where Ca as a
// function of the shape turns back) where fixing Ca would fail.
// The first step from the single starting point is a natural one: t = (0, +-1), the shape kept
// and Ca changed by `step` towards `to`.
// Step control: the predicted change of Ca is at most `step` per state (ds |t.ca| <= step) and
// the arclength step at most 2 step; it grows by 1.5 after a corrector that needed <= 3 Newton
// iterations, shrinks by 0.7 after >= 8, and halves when the corrector fails or the new secant
// turns by more than 37 degrees from the last (a jump to another branch); below step / 64 the
// branch ends (a singular point or the resolution limit of the discretisation).
// The last state lands on Ca = to exactly (the hyperplane Ca = to), and so do states at the Ca
// values of `at` wherever the branch passes them. A fold is detected when the
// secant's Ca component changes sign, and located as the vertex of the parabola Ca(s) through
// the last three points; `after_fold` more states follow on the branch beyond it. The branch also
// ends when its Ca leaves the range between `from` and `to`.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace capflow::capsule {

struct BranchPoint {
  Eigen::VectorXd y;
  double ca = 0;
};

double branch_dot(const BranchPoint& a, const BranchPoint& b);
BranchPoint branch_difference(const BranchPoint& a, const BranchPoint& b);  // a - b

struct ContinuationOptions {
  double from = 0, to = 0;  // the range of Ca
  double step = 0;          // the first and largest change of Ca per state
  int after_fold = 3;       // states beyond a fold (0: the branch ends with the state that
                            // passes it)
  std::vector<double> at;   // Ca values the branch lands on exactly where it passes them
};

// A fold located on the branch.
struct Fold {
  double ca = 0;         // the Ca of the parabola's vertex
  double arclength = 0;  // its arclength from the first point
  int after_state = 0;   // the index of the state before it
};

// The corrector: the steady state on the hyperplane <tangent, p - predicted> = 0 near
// `predicted`. Returns nullopt when it does not converge; *newton = its Newton iterations.
using BranchCorrector = std::function<std::optional<BranchPoint>(
    const BranchPoint& predicted, const BranchPoint& tangent, int* newton)>;

class ArclengthContinuation {
 public:
  // `first`: the steady state at Ca = options.from.
  ArclengthContinuation(const ContinuationOptions& options, BranchPoint first);

  enum class Status { State, Done, Stuck };
  // Computes the next state with `correct` (retrying with smaller steps): State (the new point
  // is last()), Done (the range or the states after a fold are complete), Stuck (the step fell
  // below step / 64; why() says where).
  Status advance(const BranchCorrector& correct);

  const BranchPoint& last() const { return p1_; }
  int states() const { return states_; }    // points on the branch, the first included
  double arclength() const { return s1_; }  // of last()
  const std::optional<Fold>& fold() const { return fold_; }
  bool fold_found_now() const { return fold_now_; }  // the last advance() passed the fold
  double next_step() const { return ds_; }
  int rejected() const { return rejected_; }  // corrector failures and turned secants
  const std::string& why() const { return why_; }

  // Change of the range while the branch goes on (live edits): keeps the branch.
  void set_range(double to, double step, int after_fold, const std::vector<double>& at);

 private:
  bool done() const;
  double max_step(const BranchPoint& tangent) const;
  void locate_fold();

  ContinuationOptions opt_;
  BranchPoint p0_, p1_;     // the last two points (p0 unset before the second)
  double s0_ = 0, s1_ = 0;  // their arclengths
  double sm_ = 0, cm_ = 0;  // the point before p0 (for the fold's parabola)
  double ds_ = 0;
  double dir_ = 1;  // sign of the first step in Ca
  int states_ = 1;
  int after_ = 0;  // states since the fold
  int rejected_ = 0;
  bool fold_now_ = false;
  bool landed_ = false;  // the last state is on an end of the range
  std::optional<Fold> fold_;
  std::string why_;
};

}  // namespace capflow::capsule
