// capflow/control/schedule: the Ca schedule engine with steady-state detection.
//
// Segments (control/options.h) run in order; the Ca level at the start of a segment is the level
// the previous one ended at.
//   Hold  {ca, hold}: Ca = ca; ends after hold_time, or at a steady state (hold "steady").
//   Ramp  {to, rate}: Ca(t) = c0 + sign(to - c0) rate (t - t0), clipped at `to`; ends at `to`.
//   Steps {to, by, hold}: levels c0 + k by (towards `to`, the last one clipped to `to`), each
//         held like a Hold segment.
// After the last segment the final level is held until the run ends (a constant "ca": x is one
// such final hold); a steady state there is still detected and reported once.
// Steady state: over the last `window` of simulated time, |dL/dt|, |dS/dt|, |dW/dt| (from
// samples of the inertia semi-axes) are all below `tolerance`, and the level has been held for
// at least max(min_hold, window).
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "control/options.h"

namespace capflow::control {

class CaScheduler {
 public:
  CaScheduler(const CaSchedule& schedule, const SteadyOptions& steady, double t0 = 0.0);

  // Ca at time t >= the start of the current segment (used for the RK stages of a step).
  double ca(double t) const;

  struct Event {
    bool steady = false;          // a steady state was reached at this sample
    bool level_changed = false;   // a new level/segment started
    std::string description;      // human-readable
  };
  // Feeds one shape sample at the end of a step (t, inertia semi-axes). Call at a cadence much
  // finer than `window` (every step is fine).
  Event sample(double t, double L, double S, double W);

  bool in_final_hold() const { return segment_ >= static_cast<int>(schedule_.segments.size()); }
  double level() const { return level_; }           // current base level
  double level_start() const { return level_start_; }
  int segment_index() const { return segment_; }
  // Max |rate| over the window (or +inf if not enough samples yet).
  double max_rate() const { return rate_; }
  // Estimated time until steady state (rate decaying exponentially), or -1 if unknown.
  double eta_steady(double t) const;

  // Replaces the schedule mid-run (live edit): the new segments start at time t from the current
  // Ca. Steady-state bookkeeping restarts.
  void replace(const CaSchedule& schedule, const SteadyOptions& steady, double t);

  // The engine's full state as numbers (for checkpoints; the schedule itself is not included)
  // and its restoration: restore(state()) continues bit for bit.
  std::vector<double> state() const;
  void restore(const std::vector<double>& state);  // throws std::invalid_argument if malformed

 private:
  void start_segment(int index, double t);
  void next_level(double t);

  CaSchedule schedule_;
  SteadyOptions steady_;
  int segment_ = 0;
  double level_ = 0;        // Hold/Steps: current level; Ramp: the start level c0
  double level_start_ = 0;  // time the current level (or ramp) started
  int step_index_ = 0;      // Steps: which level
  bool final_reported_ = false;
  struct Sample { double t, L, S, W; };
  std::deque<Sample> samples_;
  double rate_ = 0;
  double prev_rate_ = -1, prev_rate_t_ = 0;
};

}  // namespace capflow::control
