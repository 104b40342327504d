// capflow/render/silhouette: the surface's outline as line segments, for edge anti-aliasing
// without multisampling (CPU only, no GL).
//
// The outline of a smooth surface seen from the eye is where the normal turns perpendicular to
// the viewing direction: the zero contour of f = n . (e - x) (perspective, eye at e) or n . d
// (orthographic, d towards the viewer), with the upsampled mesh's smooth vertex normals. Each
// grid cell of each element is contoured by marching squares (f linear along the cell's edges;
// a saddle cell is resolved by the mean of its corners), so the contour is continuous across
// cells and elements (the welded vertices carry one normal). Every segment end carries the
// position, unit normal and field value interpolated along its cell edge: drawn as smooth lines
// with the surface's own shading and alpha blending, the segments blend the silhouette's
// pixels with what lies behind (the background or a farther part of the surface), which is what
// multisampling does there. Interior silhouettes (a fold in front of another part) are contours
// too; depth testing hides the parts behind the surface.
#pragma once

#include <vector>

#include "render/camera.h"
#include "render/upsample.h"

namespace capflow::render {

struct OutlineLines {
  std::vector<float> position, normal, value;  // 2 vertices per segment (GL_LINES)
  int segments() const { return static_cast<int>(value.size() / 2); }
};

// The outline of `mesh` (grid layout of upsample.h) seen by `cam` (perspective unless
// `orthographic`), into *out (storage reused).
void outline_segments(const SurfaceMesh& mesh, const Camera& cam, bool orthographic,
                      OutlineLines* out);

}  // namespace capflow::render
