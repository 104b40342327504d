#include "render/camera.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace capflow::render {
namespace {
using V3 = Eigen::Vector3d;

void view_direction(View v, V3* dir, V3* up) {
  switch (v) {
    case View::XY: *dir = V3(0, 0, 1); *up = V3(0, 1, 0); break;
    case View::XZ: *dir = V3(0, -1, 0); *up = V3(0, 0, 1); break;
    case View::YZ: *dir = V3(1, 0, 0); *up = V3(0, 0, 1); break;
    default: *dir = V3(0.55, -0.75, 0.62).normalized(); *up = V3(0, 0, 1); break;
  }
}

std::array<float, 16> to_array(const Eigen::Matrix4d& m) {
  std::array<float, 16> a{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) a[c * 4 + r] = static_cast<float>(m(r, c));
  return a;
}
}  // namespace

Camera make_camera(const CameraOptions& opt, const float bmin[3], const float bmax[3],
                   double aspect) {
  const V3 lo(bmin[0], bmin[1], bmin[2]), hi(bmax[0], bmax[1], bmax[2]);
  const double tan_half = std::tan(0.5 * opt.fov_deg * M_PI / 180.0);
  V3 eye, target, up;
  double half_h = 1, near_d = 0.01, far_d = 100;
  if (opt.view == View::Custom) {
    eye = V3(opt.eye[0], opt.eye[1], opt.eye[2]);
    target = V3(opt.target[0], opt.target[1], opt.target[2]);
    up = V3(opt.up[0], opt.up[1], opt.up[2]);
    const double dist = (eye - target).norm();
    const double r = 0.5 * (hi - lo).norm() + (0.5 * (lo + hi) - target).norm();
    half_h = dist * tan_half;
    near_d = std::max(1e-3 * dist, dist - 2 * r);
    far_d = dist + 2 * r + 1;
  } else {
    V3 dir;
    view_direction(opt.view, &dir, &up);
    target = 0.5 * (lo + hi);
    const V3 f = -dir, right = f.cross(up).normalized(), u = right.cross(f);
    double hx = 0, hy = 0, hz = 0;
    for (int c = 0; c < 8; ++c) {
      const V3 p(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z());
      const V3 d = p - target;
      hx = std::max(hx, std::abs(d.dot(right)));
      hy = std::max(hy, std::abs(d.dot(u)));
      hz = std::max(hz, std::abs(d.dot(dir)));
    }
    half_h = std::max(hy, hx / aspect) * opt.margin;
    const double dist = opt.orthographic ? 2 * hz + 1 : half_h / tan_half + hz;
    eye = target + dist * dir;
    near_d = std::max(1e-3 * dist, dist - 2 * hz);
    far_d = dist + 2 * hz + 1;
    up = u;
  }
  const V3 f = (target - eye).normalized(), s = f.cross(up).normalized(), u = s.cross(f);
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = s.transpose();
  view.block<1, 3>(1, 0) = u.transpose();
  view.block<1, 3>(2, 0) = -f.transpose();
  view(0, 3) = -s.dot(eye);
  view(1, 3) = -u.dot(eye);
  view(2, 3) = f.dot(eye);
  Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
  const double half_w = half_h * aspect;
  if (opt.orthographic) {
    proj(0, 0) = 1 / half_w;
    proj(1, 1) = 1 / half_h;
    proj(2, 2) = -2 / (far_d - near_d);
    proj(2, 3) = -(far_d + near_d) / (far_d - near_d);
    proj(3, 3) = 1;
  } else {
    const double hh = tan_half;
    proj(0, 0) = 1 / (hh * aspect);
    proj(1, 1) = 1 / hh;
    proj(2, 2) = -(far_d + near_d) / (far_d - near_d);
    proj(2, 3) = -2 * far_d * near_d / (far_d - near_d);
    proj(3, 2) = -1;
  }
  Camera cam;
  cam.view = to_array(view);
  cam.proj = to_array(proj);
  for (int c = 0; c < 3; ++c) {
    cam.eye[c] = static_cast<float>(eye[c]);
    cam.target[c] = static_cast<float>(target[c]);
    cam.up[c] = static_cast<float>(u[c]);
  }
  return cam;
}

}  // namespace capflow::render
