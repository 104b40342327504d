#include "render/color_range.h"

#include <algorithm>
#include <cmath>

namespace capflow::render {

double tick_step(double span, int target) {
  if (!(span > 0)) return 1.0;
  const double raw = span / std::max(1, target);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw * (1 - 1e-12)) return m * p;
  return 10.0 * p;
}

std::vector<double> round_ticks(double lo, double hi, int target) {
  std::vector<double> t;
  if (!std::isfinite(lo) || !std::isfinite(hi)) return t;  // no ticks for a non-finite range
  if (!(hi > lo)) return {lo};
  double step = tick_step(hi - lo, target);
  for (;;) {
    t.clear();
    const double slack = 1e-9 * (hi - lo);
    for (double k = std::ceil((lo - slack) / step); k * step <= hi + slack; k += 1.0)
      t.push_back(std::abs(k * step) < 1e-9 * step ? 0.0 : k * step);
    if (t.size() >= 2) return t;
    step = tick_step(step, 3) / 2;  // a narrow range between two ticks: a finer step
  }
}

namespace {

// [lo, hi] rounded outwards to multiples of the tick step of its span; degenerate spans widened.
void round_out(double* lo, double* hi) {
  if (!(*hi - *lo > 1e-12 * std::max(1.0, std::max(std::abs(*lo), std::abs(*hi))))) {
    const double c = 0.5 * (*lo + *hi), d = 0.5 * std::max(std::abs(c), 1.0);
    *lo = c - d;
    *hi = c + d;
  }
  const double step = tick_step(*hi - *lo);
  *lo = std::floor(*lo / step + 1e-9) * step;
  *hi = std::ceil(*hi / step - 1e-9) * step;
}

}  // namespace

ColorRange::ColorRange(RangeMode mode, bool symmetric, double fixed_lo, double fixed_hi)
    : mode_(mode), symmetric_(symmetric), lo_(fixed_lo), hi_(fixed_hi) {}

void ColorRange::update(double data_lo, double data_hi) {
  if (!std::isfinite(data_lo) || !std::isfinite(data_hi)) {
    // a frame with non-finite values (a failing run) keeps the range: it must not poison it
    under_ = over_ = false;
    if (!started_ && mode_ != RangeMode::Fixed) {
      lo_ = -0.5;
      hi_ = 0.5;
    }
    return;
  }
  if (mode_ == RangeMode::Fixed) {
    under_ = data_lo < lo_;
    over_ = data_hi > hi_;
    return;
  }
  double lo = data_lo, hi = data_hi;
  if (symmetric_) {
    const double m = std::max(std::abs(lo), std::abs(hi));
    lo = -m;
    hi = m;
  }
  if (mode_ == RangeMode::Grow && started_) {
    if (lo >= lo_ && hi <= hi_) return;  // inside: the range stays
    lo = std::min(lo, lo_);
    hi = std::max(hi, hi_);
  }
  round_out(&lo, &hi);
  if (symmetric_) {
    const double m = std::max(-lo, hi);
    lo = -m;
    hi = m;
  }
  lo_ = lo;
  hi_ = hi;
  started_ = true;
  under_ = over_ = false;
}

}  // namespace capflow::render
