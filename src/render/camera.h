// capflow/render/camera: view and projection matrices (column-major, OpenGL conventions).
//
// Named views frame the surface's bounding box: target = box centre; the eye sits along the
// view's direction at the distance where the box's projected extent, times `margin`, fills
// the image (perspective: extent / tan(fov/2) + depth half-extent; orthographic: the half
// height is the projected half extent). Custom views use eye/target/up as given; an
// orthographic custom view shows a half height of |eye - target| tan(fov/2).
#pragma once

#include <array>

#include "render/options.h"

namespace capflow::render {

struct Camera {
  std::array<float, 16> view{}, proj{};  // column-major 4x4
  std::array<float, 3> eye{}, target{}, up{};
};

Camera make_camera(const CameraOptions& opt, const float bbox_min[3], const float bbox_max[3],
                   double aspect);

}  // namespace capflow::render
