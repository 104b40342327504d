// capflow/app/progress: the progress line of `capflow run` (stderr; at most once per second on a
// terminal, every 10 s into logs). Rates count running time only: time spent paused
// (run.state "paused") is left out of steps/s and the ETA.
#pragma once

#include <functional>
#include <string>

namespace capflow::app {

class Progress {
 public:
  using Clock = std::function<double()>;  // seconds, monotonic
  // `clock`: steady_clock by default (tests pass their own).
  explicit Progress(bool tty, Clock clock = nullptr);
  // The session starts with this step count at simulated time t.
  void start(long steps, double t = 0);
  void pause();
  void unpause();
  // True when the next line is due (and marks it as printed).
  bool due();
  // Steps per second of running (unpaused) time in this session.
  double rate(long steps) const;
  // Simulated time per second of running time in this session (the ETA's rate: adaptive steps
  // vary in size).
  double time_rate(double t) const;
  bool tty() const { return tty_; }

 private:
  double running_seconds() const;
  bool tty_;
  Clock clock_;
  double start_ = 0, paused_at_ = 0, last_line_ = 0;
  bool paused_ = false, printed_ = false;
  double paused_seconds_ = 0;
  long steps_at_start_ = 0;
  double t_at_start_ = 0;
};

}  // namespace capflow::app
