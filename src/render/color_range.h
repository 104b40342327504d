// capflow/render/color_range: which values the colour map spans, frame after frame, and the
// round tick values of the colour bar.
//
// Modes (render.range):
//   Grow  ("auto", the default): the range holds every value of every frame drawn so far and
//         never shrinks, so one colour means one tension across a movie. When a frame's data
//         leave it, it grows to the union, rounded outwards to a multiple of the 1-2-5 tick step
//         of the new span (a movie's range changes a few times, each time to round values).
//   Frame ("frame"): each frame's own [min, max] (rounded outwards the same way).
//   Fixed ([min, max]): as given; values beyond it saturate, and under() / over() say so (the
//         colour bar marks them).
// Symmetric (diverging colour maps): [-m, m] with m the larger magnitude.
// A frame whose values are all equal (a sphere at rest: 0) gets [c - d, c + d], d = max(|c|, 1)/2,
// rounded out like any other. In Grow mode that width is a placeholder, not a scale: the first
// frame with a spread of values sets the range to its data and the equal value (a red cell at
// rest in its reference shape has no bending energy; once it deforms, densities of 1e-3 get a
// range of their own instead of the placeholder's unit width). A frame with non-finite values
// leaves the range as it was.
#pragma once

#include <string>
#include <vector>

namespace capflow::render {

enum class RangeMode { Grow, Frame, Fixed };

// A fixed range's bounds: both finite and within +-kMaxFixedRange, and hi - lo at least
// max(1e-12, 1e-9 max(|lo|, |hi|)), a width that double precision resolves into distinct ticks
// and colours. "" when [lo, hi] is valid, else what is wrong (e.g. "the width 2 of [1e+16,
// 1e+16] is below ...").
constexpr double kMaxFixedRange = 1e12;
std::string fixed_range_problem(double lo, double hi);

// The multiples of a 1-2-5 step (1, 2, 5 times a power of ten) in [lo, hi] (with 1e-9 of the
// span of slack at the ends), the step chosen so that there are about `target` of them (at
// least 2 for hi > lo). Always ends, for any input: a non-finite bound gives no ticks, and a
// range whose multiples double precision cannot count (a span of 2 at 1e16, an infinite span)
// gives its two ends.
std::vector<double> round_ticks(double lo, double hi, int target = 5);

// The smallest 1-2-5 step of at least span / target (target + 1 ticks or fewer).
double tick_step(double span, int target = 5);

class ColorRange {
 public:
  ColorRange(RangeMode mode, bool symmetric, double fixed_lo = 0, double fixed_hi = 1);
  // The range for the next frame, whose values span [data_lo, data_hi].
  void update(double data_lo, double data_hi);
  double lo() const { return lo_; }
  double hi() const { return hi_; }
  bool under() const { return under_; }  // this frame has values below lo()
  bool over() const { return over_; }    // ... above hi()
  RangeMode mode() const { return mode_; }

 private:
  RangeMode mode_;
  bool symmetric_;
  bool started_ = false;
  bool placeholder_ = false;   // Grow: every value so far equal to seen_lo_ (= seen_hi_)
  double seen_lo_ = 0, seen_hi_ = 0;  // Grow: the data drawn so far
  double lo_, hi_;
  bool under_ = false, over_ = false;
};

}  // namespace capflow::render
