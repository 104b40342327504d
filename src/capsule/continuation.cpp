#include "capsule/continuation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace capflow::capsule {

namespace {

constexpr double kGrow = 1.5, kShrink = 0.7;
constexpr int kFewNewton = 3, kManyNewton = 8;
constexpr double kMinCosTurn = 0.8;  // the secant may turn by at most ~37 degrees per state
constexpr double kMinStepFraction = 1.0 / 64;
constexpr double kMaxArclengthSteps = 2;  // the arclength step is at most 2 `step`

BranchPoint along(const BranchPoint& p, double ds, const BranchPoint& t) {
  return {p.y + ds * t.y, p.ca + ds * t.ca};
}

double sign(double v) {
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}

}  // namespace

double branch_dot(const BranchPoint& a, const BranchPoint& b) {
  const double n = static_cast<double>(std::max<Eigen::Index>(a.y.size(), 1));
  return a.y.dot(b.y) / n + a.ca * b.ca;
}

BranchPoint branch_difference(const BranchPoint& a, const BranchPoint& b) {
  return {a.y - b.y, a.ca - b.ca};
}

ArclengthContinuation::ArclengthContinuation(const ContinuationOptions& o, BranchPoint first)
    : opt_(o), p1_(std::move(first)) {
  if (!(o.step > 0) || o.from == o.to || o.after_fold < 0)
    throw std::invalid_argument("ArclengthContinuation: needs step > 0, from != to");
  dir_ = sign(o.to - o.from);
  ds_ = o.step;
  s1_ = 0;
}

void ArclengthContinuation::set_range(double to, double step, int after_fold,
                                      const std::vector<double>& at) {
  if (!(step > 0) || after_fold < 0)
    throw std::invalid_argument("ArclengthContinuation::set_range: needs step > 0");
  opt_.to = to;
  opt_.step = step;
  opt_.after_fold = after_fold;
  opt_.at = at;
  ds_ = std::min(ds_, step);
}

bool ArclengthContinuation::done() const {
  if (landed_) return true;
  if (fold_ && after_ >= opt_.after_fold) return true;
  // The range edited to end behind the branch (before a fold: the branch moves in dir_).
  return !fold_ && states_ > 1 && (p1_.ca - opt_.to) * dir_ >= 0;
}

double ArclengthContinuation::max_step(const BranchPoint& t) const {
  return std::min(opt_.step / std::max(std::abs(t.ca), 1e-12), kMaxArclengthSteps * opt_.step);
}

ArclengthContinuation::Status ArclengthContinuation::advance(const BranchCorrector& correct) {
  fold_now_ = false;
  if (done()) return Status::Done;
  const bool first = states_ == 1;
  BranchPoint t;
  if (first) {
    t.y = Eigen::VectorXd::Zero(p1_.y.size());
    t.ca = dir_;
  } else {
    t = branch_difference(p1_, p0_);
    const double len = std::sqrt(branch_dot(t, t));
    t.y /= len;
    t.ca /= len;
  }
  // A Ca of `at` that a corrected state passed although its predictor fell short of it.
  std::optional<double> passed;
  for (;;) {
    double ds = std::min(ds_, max_step(t));
    BranchPoint pred = along(p1_, ds, t);
    BranchPoint normal = t;
    // The end of the range the branch heads for, or a Ca of `at` passed on the way: land on it
    // exactly (the hyperplane Ca = b).
    double bound = t.ca * dir_ > 0 ? opt_.to : opt_.from;
    bool end = true;
    const double sc = sign(t.ca);
    const auto ahead = [&](double a) {
      return (a - p1_.ca) * sc > 1e-12 * std::max(1.0, std::abs(a)) && (bound - a) * sc > 0;
    };
    for (double a : opt_.at)
      if (ahead(a) && (pred.ca - a) * sc >= 0) {
        bound = a;
        end = false;
      }
    const bool forced = passed && ahead(*passed);
    if (forced) {
      bound = *passed;
      end = false;
    }
    bool landing = false;
    if (t.ca != 0 && (forced || (pred.ca - bound) * sc >= 0)) {
      ds = (bound - p1_.ca) / t.ca;
      pred = along(p1_, ds, t);
      pred.ca = bound;
      normal.y = Eigen::VectorXd::Zero(t.y.size());
      normal.ca = 1;
      landing = true;
    }
    int newton = 0;
    std::optional<BranchPoint> p = correct(pred, normal, &newton);
    if (p && !landing) {
      // the corrector carried the state past a Ca of `at`: land on that instead
      std::optional<double> first_passed;
      for (double a : opt_.at)
        if ((a - p1_.ca) * sc > 1e-12 * std::max(1.0, std::abs(a)) &&
            (p->ca - a) * sc > 1e-12 * std::max(1.0, std::abs(a)) &&
            (!first_passed || (*first_passed - a) * sc > 0))
          first_passed = a;
      if (first_passed) {
        passed = first_passed;
        continue;
      }
    }
    if (p) {
      if (landing) p->ca = bound;
      const BranchPoint sec = branch_difference(*p, p1_);
      const double len = std::sqrt(branch_dot(sec, sec));
      const bool turned = len == 0 || (!first && branch_dot(sec, t) / len < kMinCosTurn);
      if (!turned) {
        const double prev_dca = first ? dir_ : p1_.ca - p0_.ca;
        sm_ = s0_;
        cm_ = p0_.ca;
        p0_ = std::move(p1_);
        s0_ = s1_;
        p1_ = std::move(*p);
        s1_ = s0_ + len;
        ++states_;
        if (fold_) ++after_;
        landed_ = landing && end;
        if (states_ >= 3 && sign(p1_.ca - p0_.ca) * sign(prev_dca) < 0) locate_fold();
        if (newton <= kFewNewton) ds_ = ds_ * kGrow;
        if (newton >= kManyNewton) ds_ = ds_ * kShrink;
        return Status::State;
      }
    }
    ++rejected_;
    ds_ = ds / 2;
    if (ds_ < kMinStepFraction * opt_.step) {
      std::ostringstream m;
      m << "the continuation cannot go on from Ca = " << p1_.ca << ": the corrector "
        << (p ? "jumped off the branch" : "did not converge") << " down to the step " << 2 * ds_
        << " (a singular point of the branch, or the resolution limit of the mesh)";
      why_ = m.str();
      return Status::Stuck;
    }
  }
}

// The vertex of the parabola Ca(s) through the last three points (Newton's divided
// differences).
void ArclengthContinuation::locate_fold() {
  const double c0 = p0_.ca, c1 = p1_.ca;
  const double f_m0 = (c0 - cm_) / (s0_ - sm_), f_01 = (c1 - c0) / (s1_ - s0_);
  const double f2 = (f_01 - f_m0) / (s1_ - sm_);
  Fold f;
  f.after_state = states_ - 2;
  if (f2 != 0) {
    f.arclength = 0.5 * (sm_ + s0_) - f_m0 / (2 * f2);
    f.ca = cm_ + f_m0 * (f.arclength - sm_) + f2 * (f.arclength - sm_) * (f.arclength - s0_);
  } else {
    f.arclength = s0_;
    f.ca = c0;
  }
  if (!fold_) after_ = 1;
  fold_ = f;
  fold_now_ = true;
}

}  // namespace capflow::capsule
