#include "render/options.h"

namespace capflow::render {

bool RenderOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (width < 16 || height < 16 || width > 8192 || height > 8192)
    return fail("width and height must be in [16, 8192]");
  if (mp4 && (width % 2 || height % 2)) return fail("width and height must be even for MP4");
  if (msaa < 0 || msaa > 16) return fail("msaa must be in [0, 16]");
  if (subdivisions < 2 || subdivisions > 200) return fail("subdivisions must be in [2, 200]");
  if (range_mode == RangeMode::Fixed && !(range_max > range_min))
    return fail("range: max must exceed min");
  if (camera.fov_deg <= 1 || camera.fov_deg >= 170) return fail("fov must be in (1, 170) deg");
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
