// capflow/app/branch_follower: capflow steady's branch of steady states over Ca
// ("ca": {"continuation": {...}}) - pseudo-arclength continuation (capsule/continuation.h) from
// the first state, each state solved on the hyperplane of its prediction by the level solver's
// corrector (app/level_solver.h). Like the level solver it knows nothing of run directories.
#pragma once

#include <memory>

#include "app/level_solver.h"
#include "capsule/continuation.h"
#include "control/options.h"

namespace capflow::app {

class BranchFollower {
 public:
  // From the fine grid's state, a steady state at c.from.
  BranchFollower(LevelSolver& solver, Grid& fine, const control::Continuation& c);

  enum class Status {
    State,  // a new state: fine.x is it (the branch's last point)
    Done,   // the range is covered (or after_fold states past a fold)
    Stuck,  // the corrector failed at the smallest step: the branch ends (why())
  };
  struct Step {
    Status status = Status::State;
    LevelSolver::Corrections k;
    long evaluations = 0;  // velocity evaluations of this state
  };
  Step advance();

  // A live edit of the continuation's to, step, after_fold and at.
  void set_range(const control::Continuation& c);

  const capsule::ArclengthContinuation& branch() const { return *branch_; }

 private:
  LevelSolver& solver_;
  Grid& fine_;
  std::unique_ptr<capsule::ArclengthContinuation> branch_;
};

}  // namespace capflow::app
