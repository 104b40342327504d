#include "control/schedule.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace capflow::control {

namespace {
double sgn(double v) {
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}

bool same_segment(const CaSegment& a, const CaSegment& b) {
  if (a.kind != b.kind) return false;
  const bool same_hold =
      a.until_steady == b.until_steady && (a.until_steady || a.hold_time == b.hold_time);
  switch (a.kind) {
    case CaSegment::Kind::Hold:
      return a.ca == b.ca && same_hold;
    case CaSegment::Kind::Ramp:
      return a.to == b.to && a.rate == b.rate;
    case CaSegment::Kind::Steps:
      return a.to == b.to && a.by == b.by && same_hold;
  }
  return false;
}

std::string held(const CaSegment& s) {
  std::ostringstream m;
  if (s.until_steady)
    m << "held until steady";
  else
    m << "held for " << s.hold_time;
  return m.str();
}

// Levels still to come in a Steps segment from `level` (not counting it).
double levels_left(const CaSegment& s, double level) {
  return steps_levels(s, level);
}
}  // namespace

double steps_levels(const CaSegment& s, double from) {
  if (from == s.to) return 0;
  return std::ceil(std::abs(s.to - from) / s.by - 1e-12);
}

std::vector<ControlIssue> level_count_issues(const CaSchedule& sched,
                                             std::optional<double> start) {
  std::vector<ControlIssue> out;
  std::optional<double> level = start;
  for (size_t i = 0; i < sched.segments.size(); ++i) {
    const CaSegment& s = sched.segments[i];
    if (s.kind == CaSegment::Kind::Steps && level) {
      const double n = steps_levels(s, *level);
      if (n > kMaxStepsLevels) {
        std::ostringstream m;
        m << "value " << s.by << " makes " << n << " levels from Ca = " << *level << " to "
          << s.to << ": a steps segment holds at most " << kMaxStepsLevels
          << " levels (raise by)";
        out.push_back({"ca[" + std::to_string(i) + "].steps.by", m.str()});
      }
    }
    level = s.kind == CaSegment::Kind::Hold ? s.ca : s.to;
  }
  return out;
}

std::vector<double> schedule_levels(const CaSchedule& sched, double start) {
  const std::vector<ControlIssue> issues = level_count_issues(sched, start);
  if (!issues.empty()) throw std::invalid_argument(issues[0].str());
  std::vector<double> out;
  double level = start;
  for (const CaSegment& g : sched.segments) {
    switch (g.kind) {
      case CaSegment::Kind::Hold:
        out.push_back(level = g.ca);
        break;
      case CaSegment::Kind::Steps: {
        const double dir = g.to >= level ? 1.0 : -1.0;
        while (std::abs(g.to - level) > 1e-12 * std::max(1.0, g.to)) {
          level = std::abs(g.to - level) <= g.by * (1 + 1e-12) ? g.to : level + dir * g.by;
          out.push_back(level);
        }
        break;
      }
      case CaSegment::Kind::Ramp:
        throw std::invalid_argument(
            "ca: capflow steady solves at levels of Ca; a ramp has none (give a number, a list "
            "of {\"ca\": x} levels, or {\"steps\": {\"to\": ..., \"by\": ...}})");
    }
  }
  return out;
}

std::vector<double> levels_to_come(const std::vector<double>& levels, size_t done,
                                   const std::vector<double>& next) {
  done = std::min(done, levels.size());
  const bool any = done > 0;
  const double last = any ? levels[done - 1] : 0.0;
  const double dir = next.size() > 1 && next.back() < next.front() ? -1.0 : 1.0;
  std::vector<double> kept(levels.begin(), levels.begin() + static_cast<long>(done));
  for (double v : next)
    if (!any || (v - last) * dir > 0) kept.push_back(v);
  return kept;
}

std::string level_edit_problem(const CaSchedule& now, const CaSchedule& next) {
  const bool was_branch = now.continuation.has_value();
  if (was_branch != next.continuation.has_value())
    return std::string("this run ") +
           (was_branch ? "follows a continuation: edit its to, step or after_fold"
                       : "solves at levels: give levels (a continuation starts a new run)");
  if (was_branch && next.continuation->from != now.continuation->from)
    return "continuation.from cannot change once the branch has started (to, step and "
           "after_fold can)";
  if (!was_branch) {
    try {
      schedule_levels(next, 0.0);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
  }
  return "";
}

const char* const kContinuationRefused =
    "ca: a continuation follows a branch of steady states, which capflow steady solves for; "
    "capflow run holds levels, ramps and steps (a number or a list of segments)";

CaScheduler::CaScheduler(const CaSchedule& schedule, const SteadyOptions& steady, double t0,
                         std::optional<double> initial_ca)
    : schedule_(schedule), steady_(steady) {
  if (schedule_.continuation) throw std::invalid_argument(kContinuationRefused);
  if (!initial_ca && !schedule_.segments.empty() &&
      schedule_.segments[0].kind == CaSegment::Kind::Ramp)
    throw std::invalid_argument(
        "ca[0]: a schedule that begins with a ramp continues from the current Ca, and a run from "
        "rest has none (the ramp would start at Ca = 0, where the flow is singular): put a "
        "{\"ca\": x} segment first, or start from another run (start.from)");
  level_ = initial_ca.value_or(0.0);
  const std::vector<ControlIssue> too_many = level_count_issues(schedule_, level_);
  if (!too_many.empty()) throw std::invalid_argument(too_many[0].str());
  start_segment(0, t0);
}

void CaScheduler::reset_samples() {
  samples_.clear();
  rate_ = std::numeric_limits<double>::infinity();
  prev_rate_ = -1;
}

void CaScheduler::start_segment(int index, double t) {
  segment_ = index;
  level_start_ = t;
  step_index_ = 0;
  reset_samples();
  if (index >= static_cast<int>(schedule_.segments.size())) return;  // final hold of level_
  final_reported_ = false;
  const CaSegment& s = schedule_.segments[index];
  switch (s.kind) {
    case CaSegment::Kind::Hold:
      level_ = s.ca;
      break;
    case CaSegment::Kind::Ramp:
      break;  // ramps from the current level
    case CaSegment::Kind::Steps:
      step_index_ = 1;
      level_ = (std::abs(s.to - level_) <= s.by * (1 + 1e-12)) ? s.to
                                                               : level_ + sgn(s.to - level_) * s.by;
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

double CaScheduler::next_breakpoint(double t) const {
  const double none = std::numeric_limits<double>::infinity();
  if (in_final_hold()) return none;
  const CaSegment& s = schedule_.segments[segment_];
  double at = none;
  if (s.kind == CaSegment::Kind::Ramp)
    at = level_start_ + std::abs(s.to - level_) / s.rate;
  else if (!s.until_steady)
    at = level_start_ + s.hold_time;
  return at > t ? at : none;
}

void CaScheduler::next_level(double t) {
  const CaSegment& s = schedule_.segments[segment_];
  if (s.kind == CaSegment::Kind::Steps && level_ != s.to) {
    level_ =
        (std::abs(s.to - level_) <= s.by * (1 + 1e-12)) ? s.to : level_ + sgn(s.to - level_) * s.by;
    ++step_index_;
    level_start_ = t;
    reset_samples();
    return;
  }
  if (s.kind == CaSegment::Kind::Ramp) level_ = s.to;
  start_segment(segment_ + 1, t);
}

std::string CaScheduler::describe(double t) const {
  std::ostringstream m;
  if (in_final_hold()) {
    m << "schedule complete: Ca = " << level_ << " held until t_end";
    return m.str();
  }
  const CaSegment& s = schedule_.segments[segment_];
  switch (s.kind) {
    case CaSegment::Kind::Hold:
      m << "Ca = " << level_ << ", " << held(s);
      break;
    case CaSegment::Kind::Ramp: {
      const double c = ca(t);
      m << "ramp from Ca = " << c << " to " << s.to << " at " << s.rate << " per unit time";
      if (c != s.to) m << " (reaching it at t = " << t + std::abs(s.to - c) / s.rate << ")";
      break;
    }
    case CaSegment::Kind::Steps:
      m << "Ca = " << level_ << ", step " << step_index_ << " of "
        << step_index_ + static_cast<long>(levels_left(s, level_)) << " towards " << s.to << ", "
        << held(s);
      break;
  }
  return m.str();
}

std::string CaScheduler::describe_next() const {
  const int next = segment_ + 1;
  if (in_final_hold()) return "";
  if (next >= static_cast<int>(schedule_.segments.size()))
    return "then the final level is held until t_end";
  const CaSegment& s = schedule_.segments[next];
  std::ostringstream m;
  switch (s.kind) {
    case CaSegment::Kind::Hold:
      m << "then Ca = " << s.ca << ", " << held(s);
      break;
    case CaSegment::Kind::Ramp:
      m << "then ramp to Ca = " << s.to << " at " << s.rate << " per unit time";
      break;
    case CaSegment::Kind::Steps:
      m << "then steps of " << s.by << " towards Ca = " << s.to << ", each " << held(s);
      break;
  }
  return m.str();
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
  const bool held_long =
      t - level_start_ >= std::max(steady_.min_hold, steady_.window) * (1 - 1e-9);
  const bool steady = held_long && rate_ < steady_.tolerance;

  if (in_final_hold()) {
    if (steady && !final_reported_) {
      final_reported_ = true;
      ev.steady = true;
      ev.steady_ca = level_;
      std::ostringstream d;
      d << "steady state at Ca = " << level_ << " (t = " << t << ")";
      ev.description = d.str();
    }
    return ev;
  }
  const CaSegment& s = schedule_.segments[segment_];
  bool done = false;
  if (s.kind == CaSegment::Kind::Ramp) {
    done = ca(t) == s.to || t >= (level_start_ + std::abs(s.to - level_) / s.rate) * (1 - 1e-15);
  } else if (s.until_steady) {
    done = steady;
    ev.steady = steady;
    ev.steady_ca = level_;
  } else {
    done = t - level_start_ >= s.hold_time * (1 - 1e-12);
  }
  if (done) {
    std::ostringstream d;
    if (ev.steady)
      d << "steady state at Ca = " << level_ << " (t = " << t << ")";
    else if (s.kind == CaSegment::Kind::Ramp)
      d << "ramp reached Ca = " << s.to << " (t = " << t << ")";
    else
      d << "Ca = " << level_ << " held for " << s.hold_time << " (t = " << t << ")";
    next_level(t);
    ev.level_changed = true;
    // A final hold reached by a steady state has already been reported.
    if (in_final_hold() && ev.steady) final_reported_ = true;
    d << "; next: " << describe(t);
    ev.description = d.str();
  }
  return ev;
}

double CaScheduler::eta_steady(double t) const {
  if (!std::isfinite(rate_) || prev_rate_ <= 0 || !std::isfinite(prev_rate_)) return -1;
  if (rate_ < steady_.tolerance) return 0;
  if (rate_ >= prev_rate_) return -1;
  const double decay =
      std::log(prev_rate_ / rate_) / std::max(1e-12, t - prev_rate_t_ + steady_.window);
  if (decay <= 0) return -1;
  return std::log(rate_ / steady_.tolerance) / decay;
}

std::string CaScheduler::edit(const CaSchedule& next, double t) {
  const double current = ca(t);
  const CaSchedule old = schedule_;
  const int k = segment_;  // the running segment (== old size in the final hold)
  const bool prefix_kept = static_cast<int>(next.segments.size()) >= k &&
                           std::equal(old.segments.begin(), old.segments.begin() + k,
                                      next.segments.begin(), same_segment);
  schedule_ = next;
  std::ostringstream m;
  if (!prefix_kept) {
    level_ = current;
    start_segment(0, t);
    m << "new schedule from Ca = " << current << ": " << describe(t);
    return m.str();
  }
  if (k >= static_cast<int>(next.segments.size())) {
    // The running segment was removed (or the schedule was complete and stays so): hold here.
    if (k < static_cast<int>(old.segments.size())) {
      level_ = current;
      segment_ = k;
      level_start_ = t;
      reset_samples();
    }
    m << describe(t);
    return m.str();
  }
  const CaSegment& s = next.segments[k];
  if (k < static_cast<int>(old.segments.size()) && old.segments[k].kind == s.kind) {
    switch (s.kind) {
      case CaSegment::Kind::Hold:
        if (s.ca != level_) {
          level_ = s.ca;
          level_start_ = t;
          reset_samples();
        }
        break;
      case CaSegment::Kind::Ramp:
        level_ = current;
        level_start_ = t;
        break;
      case CaSegment::Kind::Steps:
        break;  // the level held goes on; later levels use the new by/to
    }
    m << "the running segment goes on: " << describe(t);
    return m.str();
  }
  level_ = current;
  start_segment(k, t);
  m << describe(t);
  return m.str();
}

std::vector<double> CaScheduler::state() const {
  std::vector<double> v = {
      static_cast<double>(segment_),       level_, level_start_, static_cast<double>(step_index_),
      final_reported_ ? 1.0 : 0.0,         rate_,  prev_rate_,   prev_rate_t_,
      static_cast<double>(samples_.size())};
  for (const Sample& s : samples_) v.insert(v.end(), {s.t, s.L, s.S, s.W});
  return v;
}

void CaScheduler::restore(const std::vector<double>& v) {
  if (v.size() < 9 || !(v[8] >= 0 && v[8] <= 1e9) || v.size() != 9 + 4 * static_cast<size_t>(v[8]))
    throw std::invalid_argument("schedule state: malformed (" + std::to_string(v.size()) +
                                " values)");
  if (!(v[0] >= 0 && v[0] <= static_cast<double>(schedule_.segments.size())))
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
