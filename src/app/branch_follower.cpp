// capflow/app/branch_follower: see branch_follower.h.
#include "app/branch_follower.h"

namespace capflow::app {

BranchFollower::BranchFollower(LevelSolver& solver, Grid& fine, const control::Continuation& c)
    : solver_(solver), fine_(fine) {
  capsule::ContinuationOptions co;
  co.from = c.from;
  co.to = c.to;
  co.step = c.step;
  co.after_fold = c.after_fold;
  co.at = c.at;
  branch_ = std::make_unique<capsule::ArclengthContinuation>(
      co,
      capsule::BranchPoint{Eigen::Map<const Eigen::VectorXd>(fine.x.data(), fine.x.size()),
                           c.from});
}

BranchFollower::Step BranchFollower::advance() {
  Step s;
  const long evals0 = fine_.cap->velocity_evaluations();
  const capsule::ArclengthContinuation::Status status =
      branch_->advance([&](const capsule::BranchPoint& p, const capsule::BranchPoint& n,
                           int* newton) { return solver_.correct(p, n, &s.k, newton); });
  s.evaluations = fine_.cap->velocity_evaluations() - evals0;
  switch (status) {
    case capsule::ArclengthContinuation::Status::Done:
      s.status = Status::Done;
      break;
    case capsule::ArclengthContinuation::Status::Stuck:
      s.status = Status::Stuck;
      break;
    default: {
      s.status = Status::State;
      const capsule::BranchPoint& p = branch_->last();
      fine_.x = Eigen::Map<const Eigen::Matrix3Xd>(p.y.data(), 3, p.y.size() / 3);
    }
  }
  return s;
}

void BranchFollower::set_range(const control::Continuation& c) {
  branch_->set_range(c.to, c.step, c.after_fold, c.at);
}

}  // namespace capflow::app
