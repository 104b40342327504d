#include "render/color_range.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace capflow::render {

double tick_step(double span, int target) {
  if (!(span > 0)) return 1.0;
  const double raw = span / std::max(1, target);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw * (1 - 1e-12)) return m * p;
  return 10.0 * p;
}

std::string fixed_range_problem(double lo, double hi) {
  std::ostringstream m;
  m << "[" << lo << ", " << hi << "]";
  const std::string shown = m.str();
  if (!std::isfinite(lo) || !std::isfinite(hi) || std::abs(lo) > kMaxFixedRange ||
      std::abs(hi) > kMaxFixedRange) {
    std::ostringstream w;
    w << shown << ": min and max must be finite and within +-" << kMaxFixedRange << " (Gs)";
    return w.str();
  }
  if (!(hi > lo)) return shown + ": max must exceed min";
  const double least = std::max(1e-12, 1e-9 * std::max(std::abs(lo), std::abs(hi)));
  if (hi - lo < least) {
    std::ostringstream w;
    w << shown << ": the width " << hi - lo << " is below " << least
      << " (1e-12, and 1e-9 of the larger bound): too narrow to tell colours apart";
    return w.str();
  }
  return "";
}

std::vector<double> round_ticks(double lo, double hi, int target) {
  std::vector<double> t;
  if (!std::isfinite(lo) || !std::isfinite(hi)) return t;  // no ticks for a non-finite range
  if (!(hi > lo)) return {lo};
  const double span = hi - lo;
  if (!std::isfinite(span)) return {lo, hi};
  double step = tick_step(span, target);
  // A few refinements at most: a narrow range between two ticks gets a finer step.
  for (int attempt = 0; attempt < 8 && std::isfinite(step) && step > 0; ++attempt) {
    const double slack = 1e-9 * span;
    const double k0 = std::ceil((lo - slack) / step), k1 = std::floor((hi + slack) / step);
    // The ticks are k * step for the integers k in [k0, k1]; beyond 1e15 a double no longer
    // counts them one by one (1e16 + 1 == 1e16), and more than 1000 is not a colour bar.
    if (!(std::abs(k0) < 1e15 && std::abs(k1) < 1e15 && k1 - k0 <= 1000)) break;
    t.clear();
    for (double k = k0; k <= k1; k += 1.0)
      t.push_back(std::abs(k * step) < 1e-9 * step ? 0.0 : k * step);
    if (t.size() >= 2) return t;
    step = tick_step(step, 3) / 2;
  }
  return {lo, hi};
}

namespace {

// [lo, hi] rounded outwards to multiples of the tick step of its span; degenerate spans widened.
void round_out(double* lo, double* hi) {
  if (!std::isfinite(*hi - *lo)) return;  // (finite data of an overflowing span: kept as is)
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
    if (placeholder_) {  // the range so far was a flat frame's placeholder: its data count
      lo = std::min(lo, seen_lo_);
      hi = std::max(hi, seen_hi_);
    } else {
      if (lo >= lo_ && hi <= hi_) return;  // inside: the range stays
      lo = std::min(lo, lo_);
      hi = std::max(hi, hi_);
    }
  }
  seen_lo_ = lo;
  seen_hi_ = hi;
  placeholder_ = !(hi - lo > 1e-12 * std::max(1.0, std::max(std::abs(lo), std::abs(hi))));
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
