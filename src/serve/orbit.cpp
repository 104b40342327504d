#include "serve/orbit.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace capflow::serve {

bool orbit_preset(const std::string& name, Orbit* out) {
  if (name == "oblique") *out = Orbit{36.25, 33.69, 1};
  else if (name == "xz") *out = Orbit{0, 0, 1};
  else if (name == "xy") *out = Orbit{0, 90, 1};
  else if (name == "yz") *out = Orbit{90, 0, 1};
  else return false;
  return true;
}

render::CameraOptions orbit_camera(const Orbit& o, const render::Snapshot& s,
                                   render::CameraOptions base) {
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -lo[k];
  }
  for (size_t i = 0; i + 2 < s.x.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], s.x[i + k]);
      hi[k] = std::max(hi[k], s.x[i + k]);
    }
  double c[3], r2 = 0;
  for (int k = 0; k < 3; ++k) {
    if (!(lo[k] <= hi[k])) lo[k] = hi[k] = 0;  // no points: the unit sphere's frame
    c[k] = 0.5 * (lo[k] + hi[k]);
    r2 += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
  }
  const double R = r2 > 0 ? std::sqrt(r2) : 1.0;
  const double deg = M_PI / 180;
  const double y = o.yaw * deg, p = o.pitch * deg;
  const double d[3] = {std::sin(y) * std::cos(p), -std::cos(y) * std::cos(p), std::sin(p)};
  const double up[3] = {-std::sin(y) * std::sin(p), std::cos(y) * std::sin(p), std::cos(p)};
  const double fov = std::clamp(base.fov_deg, 1.0, 170.0);
  const double dist = base.margin * R / std::sin(0.5 * fov * deg) / o.zoom;
  base.view = render::View::Custom;
  base.fov_deg = fov;
  for (int k = 0; k < 3; ++k) {
    base.target[k] = c[k];
    base.eye[k] = c[k] + dist * d[k];
    base.up[k] = up[k];
  }
  return base;
}

}  // namespace capflow::serve
