#include "render/colormap.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "render/data_dir.h"

namespace capflow::render {

Colormap Colormap::from_csv(const std::string& text, const std::string& origin) {
  Colormap c;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#') continue;
    std::array<float, 3> rgb{};
    char c1 = 0, c2 = 0;
    std::istringstream ls(line);
    if (!(ls >> rgb[0] >> c1 >> rgb[1] >> c2 >> rgb[2]) || c1 != ',' || c2 != ',')
      throw std::runtime_error(origin + ":" + std::to_string(lineno) + ": expected r,g,b");
    for (float v : rgb)
      if (!(v >= 0 && v <= 1))
        throw std::runtime_error(origin + ":" + std::to_string(lineno) + ": value not in [0,1]");
    c.table_.push_back(rgb);
  }
  if (c.table_.size() < 2) throw std::runtime_error(origin + ": fewer than 2 colours");
  return c;
}

Colormap Colormap::load(ColorMap m) {
  const std::string rel = std::string("assets/") + colormap_name(m) + ".csv";
  Colormap c = from_csv(read_data_file(rel), rel);
  c.diverging_ = (m == ColorMap::CoolWarm);
  return c;
}

std::array<float, 3> Colormap::at(double t) const {
  const double s = std::clamp(t, 0.0, 1.0) * static_cast<double>(table_.size() - 1);
  const size_t k = std::min(static_cast<size_t>(s), table_.size() - 2);
  const float f = static_cast<float>(s - static_cast<double>(k));
  std::array<float, 3> r{};
  for (int i = 0; i < 3; ++i) r[i] = (1 - f) * table_[k][i] + f * table_[k + 1][i];
  return r;
}

}  // namespace capflow::render
