// capflow/control/schedule: the Ca schedule engine with steady-state detection.
//
// Segments (control/options.h) run in order; the Ca level at the start of a segment is the level
// the previous one ended at (for the first segment: the initial Ca, below).
//   Hold  {ca, hold}: Ca = ca; ends after hold_time, or at a steady state (hold "steady").
//   Ramp  {to, rate}: Ca(t) = c0 + sign(to - c0) rate (t - t0), clipped at `to`; ends at `to`.
//   Steps {to, by, hold}: levels c0 + k by (towards `to`, the last one clipped to `to`), each
//         held like a Hold segment.
// After the last segment the final level is held until the run ends (a constant "ca": x is one
// such final hold); a steady state there is still detected and reported once.
// A continuation (capflow steady's) is refused: std::invalid_argument(kContinuationRefused).
// Initial Ca: the current Ca of the state the run starts from (start.from: the source run's
// Ca). From rest there is none: steps then start at 0 (the first level is `by`), and a schedule
// that begins with a ramp is refused (std::invalid_argument): Ca would pass through 0, where the
// velocity u = u_inf - f / (8 pi Ca) is singular.
// Steady state: over the last `window` of simulated time, |dL/dt|, |dS/dt|, |dW/dt| (from
// samples of the inertia semi-axes) are all below `tolerance`, and the level has been held for
// at least max(min_hold, window).
//
// Live edits of "ca" (edit()): the run never jumps back. The segments before the running one
// are compared with the new list's first entries:
//   * unchanged: completed segments are not replayed, the running segment continues with its new
//     parameters: a ramp from the current Ca at the current time (new rate, new `to`); steps from
//     the level being held (new `by` and `to` for the levels after it; the time held so far
//     counts); a hold keeps its time held unless its level changed (then Ca jumps to the new
//     level: that is what the edit asks for). Segments appended after a completed schedule start
//     from the current Ca; a running segment of another kind starts afresh from the current Ca.
//   * changed: the list is a new plan and starts at its first segment from the current Ca.
// Edits of steady.* (set_steady) keep the position in the schedule and the shape samples.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "control/control_error.h"
#include "control/options.h"

namespace capflow::control {

// Why a continuation (CaSchedule::continuation) is refused by the scheduler (capflow run).
extern const char* const kContinuationRefused;

// The most levels one steps segment may hold (ceil(|to - from| / by)): a schedule is a plan a
// person can follow, and capflow steady solves at every level.
constexpr double kMaxStepsLevels = 1e5;

// Levels a Steps segment holds from the level `from` (not counting it), as a double (no
// overflow for any by).
double steps_levels(const CaSegment& s, double from);

// Steps segments of more than kMaxStepsLevels levels, as issues at "ca[i].steps.by", each level
// followed from `start` (the Ca before the first segment; nullopt when it is not known yet, as
// with start.from before the source is read: the segments before the first Hold are not checked).
std::vector<ControlIssue> level_count_issues(const CaSchedule& s, std::optional<double> start);

// The Ca levels a schedule holds, in order, from `start` (0 from rest): capflow steady's levels.
// std::invalid_argument for a ramp (it has no levels) or a steps segment of more than
// kMaxStepsLevels levels.
std::vector<double> schedule_levels(const CaSchedule& s, double start = 0);

// A live edit of capflow steady's levels: the `done` levels of `levels` kept, then those of
// `next` beyond the last one kept, in the direction `next` moves (all of `next` when done = 0).
std::vector<double> levels_to_come(const std::vector<double>& levels, size_t done,
                                   const std::vector<double>& next);

// Why `next` cannot replace the schedule `now` of a running capflow steady ("" when it can): a
// continuation stays one (with the same from), levels stay levels that schedule_levels accepts.
std::string level_edit_problem(const CaSchedule& now, const CaSchedule& next);

class CaScheduler {
 public:
  CaScheduler(const CaSchedule& schedule, const SteadyOptions& steady, double t0 = 0.0,
              std::optional<double> initial_ca = std::nullopt);

  // Ca at time t >= the start of the current segment (used for the RK stages of a step).
  double ca(double t) const;
  // The next time after t at which the schedule changes by the clock (the end of a ramp or of
  // a timed hold), +inf when the change waits for a steady state or none is left. Adaptive time
  // steps end there, so that the change happens at its exact time.
  double next_breakpoint(double t) const;

  struct Event {
    bool steady = false;         // a steady state was reached at this sample ...
    double steady_ca = 0;        // ... at this Ca (the level held, before any level change)
    bool level_changed = false;  // a new level/segment started
    std::string description;     // human-readable: what ended and what comes next
  };
  // Feeds one shape sample at the end of a step (t, inertia semi-axes). Call at a cadence much
  // finer than `window` (every step is fine).
  Event sample(double t, double L, double S, double W);

  bool in_final_hold() const { return segment_ >= static_cast<int>(schedule_.segments.size()); }
  double level() const { return level_; }  // current base level
  double level_start() const { return level_start_; }
  int segment_index() const { return segment_; }
  // Max |rate| over the window (or +inf if not enough samples yet).
  double max_rate() const { return rate_; }
  // Estimated time until steady state (rate decaying exponentially), or -1 if unknown.
  double eta_steady(double t) const;

  // A live edit of "ca" at time t (the rule above). Returns what happens now, for the log.
  std::string edit(const CaSchedule& schedule, double t);
  // A live edit of steady.*.
  void set_steady(const SteadyOptions& steady) { steady_ = steady; }

  // What the running segment does from time t on ("ramp from Ca = 0.5 to 1 at 0.1 per unit
  // time", "Ca = 0.2, step 1 of 3 towards 0.4, held until steady", ...).
  std::string describe(double t) const;
  // What comes after the running segment ("then ramp to 1 at 0.1 per unit time", "then the
  // final level is held until t_end").
  std::string describe_next() const;

  // The engine's full state as numbers (for checkpoints; the schedule itself is not included)
  // and its restoration: restore(state()) continues bit for bit.
  std::vector<double> state() const;
  void restore(const std::vector<double>& state);  // throws std::invalid_argument if malformed

 private:
  void start_segment(int index, double t);
  void next_level(double t);
  void reset_samples();

  CaSchedule schedule_;
  SteadyOptions steady_;
  int segment_ = 0;
  double level_ = 0;        // Hold/Steps: current level; Ramp: the start level c0
  double level_start_ = 0;  // time the current level (or ramp) started
  int step_index_ = 0;      // Steps: which level
  bool final_reported_ = false;
  struct Sample {
    double t, L, S, W;
  };
  std::deque<Sample> samples_;
  double rate_ = 0;
  double prev_rate_ = -1, prev_rate_t_ = 0;
};

}  // namespace capflow::control
