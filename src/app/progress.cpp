#include "app/progress.h"

#include <algorithm>
#include <chrono>

namespace capflow::app {

Progress::Progress(bool tty, Clock clock) : tty_(tty), clock_(std::move(clock)) {
  if (!clock_)
    clock_ = [] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
          .count();
    };
}

void Progress::start(long steps, double t) {
  start_ = clock_();
  steps_at_start_ = steps;
  t_at_start_ = t;
  paused_seconds_ = 0;
  paused_ = printed_ = false;
}

void Progress::pause() {
  if (paused_) return;
  paused_ = true;
  paused_at_ = clock_();
}

void Progress::unpause() {
  if (!paused_) return;
  paused_ = false;
  paused_seconds_ += clock_() - paused_at_;
}

double Progress::running_seconds() const {
  return (paused_ ? paused_at_ : clock_()) - start_ - paused_seconds_;
}

bool Progress::due() {
  const double now = clock_();
  if (printed_ && now - last_line_ < (tty_ ? 1.0 : 10.0)) return false;
  printed_ = true;
  last_line_ = now;
  return true;
}

double Progress::rate(long steps) const {
  return (steps - steps_at_start_) / std::max(running_seconds(), 1e-9);
}

double Progress::time_rate(double t) const {
  return (t - t_at_start_) / std::max(running_seconds(), 1e-9);
}

}  // namespace capflow::app
