#include "serve/frame_query.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace capflow::serve {

namespace {

// A finite number that is the whole text, or nullopt.
std::optional<double> number(const std::string& s) {
  if (s.empty() || s.size() > 64 || s.find_first_not_of("0123456789+-.eE") != std::string::npos)
    return std::nullopt;  // decimal only: no hex, inf, nan or spaces
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
  return v;
}

struct Checker {
  const Request& r;
  std::string* error;
  // Sets *out from parameter `name` when present; false (and the message) when it is not a number
  // in [lo, hi].
  bool read(const char* name, double lo, double hi, double* out) {
    if (!r.has_param(name)) return true;
    const std::optional<double> v = number(r.param(name));
    if (!v || *v < lo || *v > hi) {
      *error = std::string(name) + " must be a number in [" + fmt(lo) + ", " + fmt(hi) +
               "], got \"" + r.param(name).substr(0, 40) + "\"";
      return false;
    }
    *out = *v;
    return true;
  }
  bool side(const char* name, int hi, int* out) {
    double v = *out;
    if (!read(name, kMinFrameSide, hi, &v)) return false;
    if (v != std::floor(v) || static_cast<long>(v) % 2 != 0) {
      *error = std::string(name) + " must be an even whole number of pixels in [" +
               std::to_string(kMinFrameSide) + ", " + std::to_string(hi) + "]";
      return false;
    }
    *out = static_cast<int>(v);
    return true;
  }
  static std::string fmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
  }
};

}  // namespace

FrameQuery parse_frame_query(const Request& r, std::string* error) {
  FrameQuery q;
  error->clear();
  Checker c{r, error};
  if (r.has_param("view") && !orbit_preset(r.param("view"), &q.orbit)) {
    *error = "view must be one of oblique, xy, xz, yz";
    return q;
  }
  if (!c.read("yaw", -3600, 3600, &q.orbit.yaw) || !c.read("pitch", -90, 90, &q.orbit.pitch) ||
      !c.read("zoom", 0.05, 20, &q.orbit.zoom) || !c.side("width", kMaxFrameWidth, &q.width) ||
      !c.side("height", kMaxFrameHeight, &q.height))
    return q;
  if (r.has_param("time")) {
    double t = 0;
    if (!c.read("time", -1e300, 1e300, &t)) return q;
    q.time = t;
  }
  if (r.has_param("field")) {
    const std::string f = r.param("field");
    if (f == "tau1") q.field = render::ColorField::MaxTension;
    else if (f == "tau2") q.field = render::ColorField::MinTension;
    else if (f == "mean") q.field = render::ColorField::MeanTension;
    else if (f == "plain") q.field = render::ColorField::Plain;
    else if (f == "curvature") q.field = render::ColorField::MeanCurvature;
    else if (f == "speed") q.field = render::ColorField::Speed;
    else if (f == "bending") q.field = render::ColorField::BendingEnergy;
    else {
      *error = "field must be one of tau1, tau2, mean, curvature, speed, bending, plain";
      return q;
    }
  }
  if (r.has_param("range")) {
    const std::string m = r.param("range");
    if (m == "grow") q.range = render::RangeMode::Grow;
    else if (m == "frame") q.range = render::RangeMode::Frame;
    else {
      *error = "range must be grow or frame";
      return q;
    }
  }
  if (r.has_param("format")) {
    const std::string f = r.param("format");
    if (f == "png") q.png = true;
    else if (f != "jpeg") {
      *error = "format must be jpeg or png";
      return q;
    }
  }
  return q;
}

}  // namespace capflow::serve
