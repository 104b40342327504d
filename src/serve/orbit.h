// capflow/serve/orbit: the console's camera as yaw, pitch and zoom about the surface's centre.
//
// The eye looks at the centre c of the surface's bounding box from the direction
//   d = (sin(yaw) cos(pitch), -cos(yaw) cos(pitch), sin(pitch))     (degrees)
// with up = dd/dpitch = (-sin(yaw) sin(pitch), cos(yaw) sin(pitch), cos(pitch)), at the distance
// where the box's circumscribed sphere (radius R), times the margin, fills the vertical field of
// view: |eye - c| = margin R / sin(fov/2) / zoom. yaw = pitch = 0 looks along +y (x right, z up);
// the presets:
//   xz (0, 0)  xy (0, 90): down -z, x right, y up  yz (90, 0): along -x, y right, z up
//   oblique (36.25, 33.69): the renderer's oblique direction (0.55, -0.75, 0.62)
#pragma once

#include <string>

#include "render/options.h"
#include "render/snapshot.h"

namespace capflow::serve {

struct Orbit {
  double yaw = 36.25, pitch = 33.69, zoom = 1;
};

// The preset called `name` (oblique|xy|xz|yz); false for another name.
bool orbit_preset(const std::string& name, Orbit* out);

// The custom camera of `o` for the surface `s` (base: fov, projection; its view becomes Custom).
render::CameraOptions orbit_camera(const Orbit& o, const render::Snapshot& s,
                                   render::CameraOptions base);

}  // namespace capflow::serve
