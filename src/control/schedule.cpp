#include "control/schedule.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace capflow::control {

namespace {
double sgn(double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); }
}

CaScheduler::CaScheduler(const CaSchedule& schedule, const SteadyOptions& steady, double t0)
    : schedule_(schedule), steady_(steady) {
  level_ = schedule_.segments.empty() ? 0.0 : schedule_.segments[0].ca;
  start_segment(0, t0);
}

void CaScheduler::start_segment(int index, double t) {
  segment_ = index;
  level_start_ = t;
  step_index_ = 0;
  samples_.clear();
  rate_ = std::numeric_limits<double>::infinity();
  prev_rate_ = -1;
  if (index >= static_cast<int>(schedule_.segments.size())) return;  // final hold of level_
  const CaSegment& s = schedule_.segments[index];
  switch (s.kind) {
    case CaSegment::Kind::Hold: level_ = s.ca; break;
    case CaSegment::Kind::Ramp: break;  // ramps from the current level
    case CaSegment::Kind::Steps:
      step_index_ = 1;
      level_ = (std::abs(s.to - level_) <= s.by) ? s.to : level_ + sgn(s.to - level_) * s.by;
      break;
  }
}

double CaScheduler::ca(double t) const {
  if (in_final_hold()) return level_;
  const CaSegment& s = schedule_.segments[segment_];
  if (s.kind != CaSegment::Kind::Ramp) return level_;
  const double c = level_ + sgn(s.to - level_) * s.rate * (t - level_start_);
  return (s.to >= level_) ? std::min(c, s.to) : std::max(c, s.to);
}

void CaScheduler::next_level(double t) {
  const CaSegment& s = schedule_.segments[segment_];
  if (s.kind == CaSegment::Kind::Steps && level_ != s.to) {
    level_ = (std::abs(s.to - level_) <= s.by * (1 + 1e-12)) ? s.to : level_ + sgn(s.to - level_) * s.by;
    ++step_index_;
    level_start_ = t;
    samples_.clear();
    rate_ = std::numeric_limits<double>::infinity();
    prev_rate_ = -1;
    return;
  }
  if (s.kind == CaSegment::Kind::Ramp) level_ = s.to;
  start_segment(segment_ + 1, t);
}

CaScheduler::Event CaScheduler::sample(double t, double L, double S, double W) {
  Event ev;
  samples_.push_back({t, L, S, W});
  // Keep just over one window of samples.
  while (samples_.size() > 2 && samples_[1].t <= t - steady_.window) samples_.pop_front();
  if (samples_.size() >= 2 && t - samples_.front().t >= steady_.window * (1 - 1e-9)) {
    const Sample& a = samples_.front();
    const double dt = t - a.t;
    const double r = std::max({std::abs(L - a.L), std::abs(S - a.S), std::abs(W - a.W)}) / dt;
    if (prev_rate_ < 0 || t - prev_rate_t_ >= steady_.window) {
      prev_rate_ = rate_;
      prev_rate_t_ = t;
    }
    rate_ = r;
  }
  const bool held = t - level_start_ >= std::max(steady_.min_hold, steady_.window) * (1 - 1e-9);
  const bool steady = held && rate_ < steady_.tolerance;

  if (in_final_hold()) {
    if (steady && !final_reported_) {
      final_reported_ = true;
      ev.steady = true;
      std::ostringstream d;
      d << "steady state at Ca = " << level_ << " (t = " << t << ")";
      ev.description = d.str();
    }
    return ev;
  }
  const CaSegment& s = schedule_.segments[segment_];
  bool done = false;
  if (s.kind == CaSegment::Kind::Ramp) {
    done = (ca(t) == s.to);
  } else if (s.until_steady) {
    done = steady;
    ev.steady = steady;
  } else {
    done = t - level_start_ >= s.hold_time * (1 - 1e-12);
  }
  if (done) {
    const double old = (s.kind == CaSegment::Kind::Ramp) ? s.to : level_;
    std::ostringstream d;
    if (ev.steady) d << "steady state at Ca = " << old << " (t = " << t << "); ";
    next_level(t);
    ev.level_changed = true;
    if (in_final_hold()) {
      d << "schedule complete, holding Ca = " << level_;
      // A final hold reached by a steady state has already been reported.
      if (ev.steady) final_reported_ = true;
    } else {
      d << "Ca -> " << ca(t);
    }
    ev.description = d.str();
  }
  return ev;
}

double CaScheduler::eta_steady(double t) const {
  if (!std::isfinite(rate_) || prev_rate_ <= 0 || !std::isfinite(prev_rate_)) return -1;
  if (rate_ < steady_.tolerance) return 0;
  if (rate_ >= prev_rate_) return -1;
  const double decay = std::log(prev_rate_ / rate_) / std::max(1e-12, t - prev_rate_t_ + steady_.window);
  if (decay <= 0) return -1;
  return std::log(rate_ / steady_.tolerance) / decay;
}

void CaScheduler::replace(const CaSchedule& schedule, const SteadyOptions& steady, double t) {
  const double current = ca(t);
  schedule_ = schedule;
  steady_ = steady;
  level_ = current;
  final_reported_ = false;
  start_segment(0, t);
}

std::vector<double> CaScheduler::state() const {
  std::vector<double> v = {static_cast<double>(segment_), level_, level_start_,
                           static_cast<double>(step_index_), final_reported_ ? 1.0 : 0.0, rate_,
                           prev_rate_, prev_rate_t_, static_cast<double>(samples_.size())};
  for (const Sample& s : samples_) v.insert(v.end(), {s.t, s.L, s.S, s.W});
  return v;
}

void CaScheduler::restore(const std::vector<double>& v) {
  if (v.size() < 9 || v.size() != 9 + 4 * static_cast<size_t>(v[8]))
    throw std::invalid_argument("schedule state: malformed (" + std::to_string(v.size()) + " values)");
  if (v[0] < 0 || v[0] > static_cast<double>(schedule_.segments.size()))
    throw std::invalid_argument("schedule state: segment index " + std::to_string(v[0]) +
                                " does not fit the schedule (" +
                                std::to_string(schedule_.segments.size()) + " segments)");
  segment_ = static_cast<int>(v[0]);
  level_ = v[1];
  level_start_ = v[2];
  step_index_ = static_cast<int>(v[3]);
  final_reported_ = v[4] != 0;
  rate_ = v[5];
  prev_rate_ = v[6];
  prev_rate_t_ = v[7];
  samples_.clear();
  for (size_t k = 9; k < v.size(); k += 4) samples_.push_back({v[k], v[k + 1], v[k + 2], v[k + 3]});
}

}  // namespace capflow::control
