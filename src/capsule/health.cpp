#include "capsule/health.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "geometry/surface.h"
#include "spectral/spectral.h"

namespace capflow::capsule {

namespace {
std::string where(const geometry::Mesh& mesh, int m, const Eigen::Vector3d& p,
                  const char* label = "position") {
  const int nb = mesh.nb();
  std::ostringstream s;
  s << "element " << m / (nb * nb) << ", node (" << m % nb << ", " << (m / nb) % nb << "), "
    << label << " (" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}
}  // namespace

HealthMonitor::HealthMonitor(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x0,
                             HealthOptions opt)
    : mesh_(mesh), opt_(opt) {
  const int nb = mesh.nb();
  // Legendre Vandermonde at the Lobatto nodes; the last row of its inverse gives the
  // coefficient of P_{nb-1}.
  Eigen::MatrixXd v(nb, nb);
  for (int i = 0; i < nb; ++i)
    for (int k = 0; k < nb; ++k) {
      double p;
      spectral::legendre(k, mesh.nodes()[i], &p, nullptr);
      v(i, k) = p;
    }
  modal_last_ = v.inverse().row(nb - 1);
  normals_ = geometry::compute_geometry(mesh, x0).n;
  last_x_ = x0;
}

double HealthMonitor::oscillation_indicator(const Eigen::Matrix3Xd& x) const {
  const int nb = mesh_.nb();
  double worst = 0;
  for (int e = 0; e < mesh_.ne(); ++e) {
    const double size = (x.col(mesh_.local(e, 0, 0)) - x.col(mesh_.local(e, nb - 1, nb - 1))).norm();
    for (int line = 0; line < nb; ++line)
      for (int dir = 0; dir < 2; ++dir) {
        Eigen::Vector3d a = Eigen::Vector3d::Zero();
        for (int k = 0; k < nb; ++k)
          a += modal_last_(0, k) * x.col(dir == 0 ? mesh_.local(e, k, line) : mesh_.local(e, line, k));
        worst = std::max(worst, a.norm() / size);
      }
  }
  return worst;
}

void HealthMonitor::restore(const Eigen::Matrix3Xd& normals, const std::vector<double>& flags) {
  if (flags.size() != 3 && flags.size() != 4)
    throw std::invalid_argument("health flags: expected 3 or 4 values, got " +
                                std::to_string(flags.size()));
  normals_ = normals;
  warned_oscillation_ = flags[0] != 0;
  warned_wrinkle_ = flags[1] != 0;
  compressive_since_ = flags[2];
  warned_resolution_ = flags.size() == 4 && flags[3] != 0;
}

HealthReport HealthMonitor::check(const Eigen::Matrix3Xd& x, double t) {
  HealthReport r;
  for (int m = 0; m < x.cols(); ++m)
    if (!x.col(m).allFinite()) {
      r.level = HealthLevel::Failure;
      r.cause = "nan";
      r.message = "non-finite node position at t = " + std::to_string(t) + " at " +
                  where(mesh_, m, last_x_.col(m), "last good position");
      return r;
    }
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh_, x);
  for (int m = 0; m < x.cols(); ++m) {
    if (g.t1.col(m).cross(g.t2.col(m)).dot(normals_.col(m)) <= 0) {
      r.level = HealthLevel::Failure;
      r.cause = "jacobian";
      r.message = "element Jacobian changed sign at t = " + std::to_string(t) + " at " +
                  where(mesh_, m, last_x_.col(m), "last good position");
      return r;
    }
  }
  r.indicator = oscillation_indicator(x);
  const bool fail = r.indicator > opt_.oscillation_fail;
  if (fail || (r.indicator > opt_.oscillation_warn && !warned_oscillation_)) {
    r.level = fail ? HealthLevel::Failure : HealthLevel::Warning;
    r.cause = "oscillation";
    std::ostringstream s;
    s << (fail ? "runaway node-to-node oscillation" : "node-to-node oscillation growing")
      << " at t = " << t << ": highest-mode amplitude " << r.indicator << " of the element size ("
      << (fail ? "limit " : "failure at ") << opt_.oscillation_fail << ")";
    r.message = s.str();
    if (fail) return r;
    warned_oscillation_ = true;
  }
  if (r.level == HealthLevel::Ok && !warned_resolution_) {
    int m = 0;
    const double turn = geometry::max_normal_turning(mesh_, g.n, &m);
    if (turn > opt_.resolution_warn_angle) {
      warned_resolution_ = true;
      r.level = HealthLevel::Warning;
      r.cause = "resolution";
      std::ostringstream s;
      s << "surface under-resolved at t = " << t << ": the normal turns by " << turn
        << " rad between neighbouring nodes at " << where(mesh_, m, x.col(m))
        << " (warning above " << opt_.resolution_warn_angle
        << "); a tip sharper than NB resolves: the velocity and volume lose accuracy there, "
           "raise mesh.nb";
      r.message = s.str();
    }
  }
  normals_ = g.n;
  last_x_ = x;
  return r;
}

HealthReport HealthMonitor::check_wrinkling(double t, double min_tension,
                                            const Eigen::Vector3d& at, double d_rate) {
  HealthReport r;
  const bool compressive = min_tension < opt_.wrinkle_tension && std::abs(d_rate) < opt_.wrinkle_rate;
  if (!compressive) {
    compressive_since_ = -1;
    return r;
  }
  if (compressive_since_ < 0) compressive_since_ = t;
  if (!warned_wrinkle_ && t - compressive_since_ >= opt_.wrinkle_duration) {
    warned_wrinkle_ = true;
    r.level = HealthLevel::Warning;
    r.cause = "wrinkling";
    std::ostringstream s;
    s << "compressive tension " << min_tension << " persists near steady state since t = "
      << compressive_since_ << " (now t = " << t << ") at (" << at.x() << ", " << at.y() << ", "
      << at.z() << "): the membrane would wrinkle there (paper: Ca below ~0.15)";
    r.message = s.str();
  }
  return r;
}

}  // namespace capflow::capsule
