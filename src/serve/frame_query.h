// capflow/serve/frame_query: GET /api/frame's query parameters, checked.
//
//   yaw, pitch, zoom  the orbit camera (serve/orbit.h): yaw in [-3600, 3600], pitch in [-90, 90]
//                     degrees, zoom in [0.05, 20]; or view=oblique|xy|xz|yz (a preset, zoom
//                     still applies)
//   field             tau1 | tau2 | mean | curvature | speed | plain (default tau1)
//   range             grow | frame (the colour range: grown over the frames drawn, or each
//                     frame's own; default grow)
//   width, height     even, in [64, 2560] x [64, 1440] (default 1280 x 720)
//   time              a saved surface: the one nearest this time (default: the newest state)
//   format            jpeg | png (default jpeg)
// A bad value is refused naming the parameter and its valid range.
#pragma once

#include <optional>
#include <string>

#include "render/options.h"
#include "serve/http.h"
#include "serve/orbit.h"

namespace capflow::serve {

constexpr int kMaxFrameWidth = 2560, kMaxFrameHeight = 1440, kMinFrameSide = 64;

struct FrameQuery {
  Orbit orbit;
  render::ColorField field = render::ColorField::MaxTension;
  render::RangeMode range = render::RangeMode::Grow;
  int width = 1280, height = 720;
  std::optional<double> time;
  bool png = false;
};

// The query of `r`; "" in *error, or what is wrong (then the result is meaningless).
FrameQuery parse_frame_query(const Request& r, std::string* error);

}  // namespace capflow::serve
