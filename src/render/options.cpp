#include "render/options.h"

#include <cmath>
#include <sstream>

namespace capflow::render {

std::string custom_camera_problem(const CameraOptions& c) {
  const auto finite = [](const std::array<double, 3>& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) &&
           std::abs(v[0]) <= 1e6 && std::abs(v[1]) <= 1e6 && std::abs(v[2]) <= 1e6;
  };
  const auto show = [](const std::array<double, 3>& v) {
    std::ostringstream s;
    s << v[0] << "," << v[1] << "," << v[2];
    return s.str();
  };
  if (!finite(c.eye)) return "eye " + show(c.eye) + ": three finite numbers within +-1e6";
  if (!finite(c.target)) return "target " + show(c.target) + ": three finite numbers within +-1e6";
  if (!finite(c.up)) return "up " + show(c.up) + ": three finite numbers within +-1e6";
  const double d[3] = {c.eye[0] - c.target[0], c.eye[1] - c.target[1], c.eye[2] - c.target[2]};
  const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(dist > 1e-6)) return "eye " + show(c.eye) + " is at the target: they must differ";
  const double up = std::sqrt(c.up[0] * c.up[0] + c.up[1] * c.up[1] + c.up[2] * c.up[2]);
  const double cr[3] = {d[1] * c.up[2] - d[2] * c.up[1], d[2] * c.up[0] - d[0] * c.up[2],
                        d[0] * c.up[1] - d[1] * c.up[0]};
  const double sin = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) / (dist * up);
  if (!(up > 0) || !(sin > 1e-6))
    return "up " + show(c.up) + " is zero or along the line of sight: give a direction across it";
  return "";
}

bool RenderOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (width < 16 || height < 16 || width > kMaxWidth || height > kMaxHeight)
    return fail("width must be in [16, " + std::to_string(kMaxWidth) + "] and height in [16, " +
                std::to_string(kMaxHeight) + "]");
  if (mp4 && (width % 2 || height % 2)) return fail("width and height must be even for MP4");
  if (msaa < 0 || msaa > 16) return fail("msaa must be in [0, 16]");
  if (subdivisions < 2 || subdivisions > 200) return fail("subdivisions must be in [2, 200]");
  if (range_mode == RangeMode::Fixed) {
    const std::string r = fixed_range_problem(range_min, range_max);
    if (!r.empty()) return fail("range " + r);
  }
  if (!(camera.fov_deg > 1 && camera.fov_deg < 170)) return fail("fov must be in (1, 170) deg");
  if (!(camera.margin > 0 && camera.margin < 100)) return fail("margin must be in (0, 100)");
  if (camera.view == View::Custom) {
    const std::string c = custom_camera_problem(camera);
    if (!c.empty()) return fail(c);
  }
  if (fps < 1 || fps > 240) return fail("fps must be in [1, 240]");
  if (crf < 0 || crf > 51) return fail("crf (quality) must be in [0, 51]");
  if (flush_every < 1) return fail("flush_every must be >= 1");
  if (queue_capacity < 1) return fail("queue_capacity must be >= 1");
  return true;
}

const char* view_name(View v) {
  switch (v) {
    case View::Oblique:
      return "oblique";
    case View::XY:
      return "xy";
    case View::XZ:
      return "xz";
    case View::YZ:
      return "yz";
    default:
      return "custom";
  }
}
const char* field_name(ColorField f) {
  switch (f) {
    case ColorField::MaxTension:
      return "max";
    case ColorField::MinTension:
      return "min";
    case ColorField::MeanTension:
      return "mean";
    case ColorField::MeanCurvature:
      return "curvature";
    case ColorField::Speed:
      return "speed";
    case ColorField::BendingEnergy:
      return "bending";
    default:
      return "plain";
  }
}
const char* field_label(ColorField f) {
  switch (f) {
    case ColorField::MaxTension:
      return "\u03c4\u2081 / G\u209b";  // tau_1 / G_s
    case ColorField::MinTension:
      return "\u03c4\u2082 / G\u209b";
    case ColorField::MeanTension:
      return "(\u03c4\u2081 + \u03c4\u2082) / 2G\u209b";
    case ColorField::MeanCurvature:
      return "H a";
    case ColorField::Speed:
      return "|u| / G a";
    case ColorField::BendingEnergy:
      return "bending energy / G\u209b";
    default:
      return "";
  }
}
const char* colormap_name(ColorMap m) {
  return m == ColorMap::Viridis ? "viridis" : "coolwarm";
}
const char* antialias_name(Antialias a) {
  switch (a) {
    case Antialias::Multisample:
      return "msaa";
    case Antialias::Lines:
      return "lines";
    case Antialias::Off:
      return "off";
    default:
      return "auto";
  }
}
bool parse_antialias(const std::string& s, Antialias* out) {
  for (Antialias a : {Antialias::Auto, Antialias::Multisample, Antialias::Lines, Antialias::Off})
    if (s == antialias_name(a)) {
      *out = a;
      return true;
    }
  return false;
}

const char* backend_name(Backend b) {
  switch (b) {
    case Backend::Egl: return "egl";
    case Backend::OSMesa: return "osmesa";
    default: return "auto";
  }
}

bool parse_backend(const std::string& s, Backend* out) {
  if (s == "auto") *out = Backend::Auto;
  else if (s == "egl") *out = Backend::Egl;
  else if (s == "osmesa") *out = Backend::OSMesa;
  else return false;
  return true;
}

bool parse_view(const std::string& s, View* out) {
  if (s == "oblique")
    *out = View::Oblique;
  else if (s == "xy")
    *out = View::XY;
  else if (s == "xz")
    *out = View::XZ;
  else if (s == "yz")
    *out = View::YZ;
  else
    return false;
  return true;
}
bool parse_field(const std::string& s, ColorField* out) {
  if (s == "max" || s == "max-tension")
    *out = ColorField::MaxTension;
  else if (s == "min" || s == "min-tension")
    *out = ColorField::MinTension;
  else if (s == "mean" || s == "mean-tension")
    *out = ColorField::MeanTension;
  else if (s == "plain")
    *out = ColorField::Plain;
  else if (s == "bending" || s == "bending-energy")
    *out = ColorField::BendingEnergy;
  else
    return false;
  return true;
}
bool parse_colormap(const std::string& s, ColorMap* out) {
  if (s == "viridis")
    *out = ColorMap::Viridis;
  else if (s == "coolwarm")
    *out = ColorMap::CoolWarm;
  else
    return false;
  return true;
}

}  // namespace capflow::render
