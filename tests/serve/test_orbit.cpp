// serve/orbit: the console's camera. The presets look along the renderer's named directions, the
// up vector is perpendicular to the line of sight, and the sphere around the box fills the view.
#include <gtest/gtest.h>

#include <cmath>

#include "serve/orbit.h"

namespace capflow::serve {
namespace {

render::Snapshot box(double ax, double ay, double az, double cx = 0) {
  render::Snapshot s;
  s.x = {cx - ax, -ay, -az, cx + ax, ay, az};
  return s;
}

std::array<double, 3> dir(const render::CameraOptions& c) {
  std::array<double, 3> d;
  double n = 0;
  for (int k = 0; k < 3; ++k) n += std::pow(c.eye[k] - c.target[k], 2);
  for (int k = 0; k < 3; ++k) d[k] = (c.eye[k] - c.target[k]) / std::sqrt(n);
  return d;
}

TEST(Orbit, PresetsLookAlongTheNamedAxes) {
  struct Case {
    const char* name;
    std::array<double, 3> eye_dir, up;
  };
  for (const Case& c : {Case{"xy", {0, 0, 1}, {0, 1, 0}}, Case{"xz", {0, -1, 0}, {0, 0, 1}},
                        Case{"yz", {1, 0, 0}, {0, 0, 1}}}) {
    Orbit o;
    ASSERT_TRUE(orbit_preset(c.name, &o));
    const render::CameraOptions cam = orbit_camera(o, box(1, 1, 1), {});
    const auto d = dir(cam);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(d[k], c.eye_dir[k], 1e-12) << c.name;
      EXPECT_NEAR(cam.up[k], c.up[k], 1e-12) << c.name;
    }
    EXPECT_EQ(cam.view, render::View::Custom);
  }
  Orbit o;
  ASSERT_TRUE(orbit_preset("oblique", &o));
  const auto d = dir(orbit_camera(o, box(1, 1, 1), {}));
  const double n = std::sqrt(0.55 * 0.55 + 0.75 * 0.75 + 0.62 * 0.62);
  EXPECT_NEAR(d[0], 0.55 / n, 2e-4);
  EXPECT_NEAR(d[1], -0.75 / n, 2e-4);
  EXPECT_NEAR(d[2], 0.62 / n, 2e-4);
  EXPECT_FALSE(orbit_preset("top", &o));
}

TEST(Orbit, UpIsPerpendicularAndTheBoxFillsTheView) {
  for (double yaw : {-400.0, -90.0, 0.0, 33.0, 181.0})
    for (double pitch : {-90.0, -45.0, 0.0, 12.0, 90.0})
      for (double zoom : {0.5, 1.0, 3.0}) {
        render::CameraOptions base;
        base.fov_deg = 30;
        base.margin = 1.1;
        const render::CameraOptions c = orbit_camera({yaw, pitch, zoom}, box(2, 1, 0.5, 3), base);
        const auto d = dir(c);
        double dot = 0, up = 0, dist = 0;
        for (int k = 0; k < 3; ++k) {
          dot += d[k] * c.up[k];
          up += c.up[k] * c.up[k];
          dist += std::pow(c.eye[k] - c.target[k], 2);
        }
        EXPECT_NEAR(dot, 0, 1e-12);
        EXPECT_NEAR(up, 1, 1e-12);
        EXPECT_NEAR(c.target[0], 3, 1e-12);
        const double R = std::sqrt(4 + 1 + 0.25);
        EXPECT_NEAR(std::sqrt(dist), 1.1 * R / std::sin(15 * M_PI / 180) / zoom, 1e-9);
      }
}

}  // namespace
}  // namespace capflow::serve
