// render/options: RenderOptions::IsValid and the custom camera refuse what cannot be drawn (NaN
// eye or field of view, an eye at its target, up along the line of sight, a range double
// precision cannot resolve) instead of drawing an empty image.
#include <gtest/gtest.h>

#include <cmath>

#include "render/options.h"

using namespace capflow::render;

namespace {
std::string problem(const RenderOptions& o) {
  std::string e;
  return o.IsValid(&e) ? "" : e;
}
}  // namespace

TEST(RenderOptions, CustomCamerasMustBeDrawable) {
  CameraOptions c;
  c.view = View::Custom;
  EXPECT_EQ(custom_camera_problem(c), "");
  c.eye = {NAN, 0, 0};
  EXPECT_NE(custom_camera_problem(c).find("eye nan,0,0"), std::string::npos);
  c.eye = {0, 0, 0};
  EXPECT_NE(custom_camera_problem(c).find("is at the target"), std::string::npos);
  c.eye = {0, 0, 5};  // looking along -z with up +z
  EXPECT_NE(custom_camera_problem(c).find("along the line of sight"), std::string::npos);
  c.eye = {0, -6, 0};
  c.up = {0, 0, 0};
  EXPECT_NE(custom_camera_problem(c).find("up 0,0,0"), std::string::npos);
  c.up = {0, 0, 1};
  c.target = {1e300, 0, 0};
  EXPECT_NE(custom_camera_problem(c).find("target"), std::string::npos);
}

TEST(RenderOptions, FieldOfViewSizesAndRanges) {
  RenderOptions o;
  EXPECT_EQ(problem(o), "");
  o.camera.fov_deg = NAN;
  EXPECT_NE(problem(o).find("fov"), std::string::npos);
  o.camera.fov_deg = 30;
  o.width = kMaxWidth + 2;
  EXPECT_NE(problem(o).find("width must be in [16, 7680]"), std::string::npos);
  o.width = 1280;
  o.range_mode = RangeMode::Fixed;
  o.range_min = 1e16;
  o.range_max = 1e16 + 2;
  EXPECT_NE(problem(o).find("range"), std::string::npos);
  o.range_min = 0;
  o.range_max = 1;
  EXPECT_EQ(problem(o), "");
  o.camera.view = View::Custom;
  o.camera.eye = {0, 0, NAN};
  EXPECT_NE(problem(o).find("eye"), std::string::npos);
}
