// capflow/render/colormap: perceptual colour maps read from assets/<name>.csv (one "r,g,b"
// row per entry, sRGB in [0,1], '#' comments) and evaluated by linear interpolation:
//   c(t) = (1-f) c_k + f c_{k+1},  s = clamp(t,0,1) (n-1), k = floor(s), f = s - k.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "render/options.h"

namespace capflow::render {

class Colormap {
 public:
  // Loads assets/<colormap_name(m)>.csv via find_data_file; throws on a missing/bad file.
  static Colormap load(ColorMap m);
  static Colormap from_csv(const std::string& text, const std::string& origin);

  std::array<float, 3> at(double t) const;  // t in [0,1] (clamped)
  const std::vector<std::array<float, 3>>& table() const { return table_; }
  bool diverging() const { return diverging_; }

 private:
  std::vector<std::array<float, 3>> table_;
  bool diverging_ = false;
};

}  // namespace capflow::render
