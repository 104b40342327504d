// The outline of the upsampled surface (render/silhouette.h, CPU only): on the unit sphere the
// zero contour of n . (e - x) is a known circle - z = 0 seen orthographically along z, z = 1/d
// from an eye at distance d on the z axis - and it is closed: every segment end is shared with
// exactly one other segment (across cells and elements).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "render/camera.h"
#include "render/silhouette.h"
#include "render/upsample.h"

namespace capflow::render {
namespace {

SurfaceMesh sphere_mesh(int ne, int nb) {
  geometry::Mesh mesh(ne, nb);
  const auto& x = mesh.reference();
  Snapshot s;
  s.ne = ne;
  s.nb = nb;
  s.x.resize(3 * static_cast<size_t>(mesh.num_local()));
  s.tau1.assign(mesh.num_local(), 1.0);
  s.tau2.assign(mesh.num_local(), 1.0);
  for (int k = 0; k < mesh.num_local(); ++k)
    for (int d = 0; d < 3; ++d) s.x[3 * k + d] = x(d, k);
  SurfaceMesh m;
  Upsampler(nb, 25).build(s, ColorField::MaxTension, &m);
  return m;
}

Camera camera(View view, bool ortho, const SurfaceMesh& m, const std::array<double, 3>& eye = {}) {
  CameraOptions o;
  o.view = view;
  o.orthographic = ortho;
  if (view == View::Custom) {
    o.eye = eye;
    o.target = {0, 0, 0};
    o.up = {0, 1, 0};
  }
  return make_camera(o, m.bbox_min, m.bbox_max, 16.0 / 9.0);
}

// Largest distance from the expected circle (in the plane z = z0, radius r) and the number of
// segment ends not shared by exactly two segments.
void check_circle(const OutlineLines& o, double z0, double r, double* worst, int* open_ends) {
  *worst = 0;
  const int n = 2 * o.segments();
  std::vector<std::array<double, 3>> p(n);
  for (int k = 0; k < n; ++k) {
    for (int d = 0; d < 3; ++d) p[k][d] = o.position[3 * k + d];
    const double rho = std::hypot(p[k][0], p[k][1]);
    *worst = std::max({*worst, std::abs(p[k][2] - z0), std::abs(rho - r)});
  }
  *open_ends = 0;
  for (int k = 0; k < n; ++k) {
    int same = 0;
    for (int q = 0; q < n; ++q)
      if (std::abs(p[q][0] - p[k][0]) + std::abs(p[q][1] - p[k][1]) + std::abs(p[q][2] - p[k][2]) <
          1e-5)
        ++same;
    *open_ends += same != 2;
  }
}

TEST(Silhouette, OrthographicSphereOutlineIsTheEquator) {
  for (int ne : {6, 10}) {
    const SurfaceMesh m = sphere_mesh(ne, 10);
    OutlineLines o;
    outline_segments(m, camera(View::XY, true, m), true, &o);
    double worst;
    int open_ends;
    check_circle(o, 0.0, 1.0, &worst, &open_ends);
    EXPECT_GT(o.segments(), 100) << "NE=" << ne;
    EXPECT_LT(worst, 2e-3) << "NE=" << ne;  // linear interpolation along 1/24-element cells
    EXPECT_EQ(open_ends, 0) << "NE=" << ne;
    for (int k = 0; k < 2 * o.segments(); ++k) {  // the normal there is horizontal, unit
      EXPECT_NEAR(o.normal[3 * k + 2], 0.0, 2e-3);
      EXPECT_NEAR(std::hypot(o.normal[3 * k], o.normal[3 * k + 1]), 1.0, 1e-6);
    }
  }
}

TEST(Silhouette, PerspectiveSphereOutlineIsTheTangentCircle) {
  const SurfaceMesh m = sphere_mesh(6, 10);
  const double d = 4.0;
  OutlineLines o;
  outline_segments(m, camera(View::Custom, false, m, {0, 0, d}), false, &o);
  // tangent points from the eye: x . e = 1, i.e. z = 1/d on a circle of radius sqrt(1 - 1/d^2)
  double worst;
  int open_ends;
  check_circle(o, 1.0 / d, std::sqrt(1.0 - 1.0 / (d * d)), &worst, &open_ends);
  EXPECT_GT(o.segments(), 100);
  EXPECT_LT(worst, 2e-3);
  EXPECT_EQ(open_ends, 0);
}

}  // namespace
}  // namespace capflow::render
