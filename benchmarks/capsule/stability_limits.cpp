// Study program (Milestone 8, Deliver 2): the stability limit of fixed RK4 steps, measured.
//
// For the state of a control file (the sphere at rest, or the shape of a checkpoint given with
// start.from, e.g. a steady state of capflow steady) the growth per step of a small perturbation
// under the step map Phi_h (classical RK4 at the control file's Ca, then the capsule's
// end-of-step smoothing, as `capflow run` steps with a fixed time.dt) is measured by power
// iteration: delta <- Phi_h(x + delta) - Phi_h(x), rescaled to 1e-7 of the shape each time;
// the growth rho(h) is the geometric mean of |delta_new| / |delta| over the last 10 of 30
// iterations. The limit h* is where rho crosses 1.02: bracketed by doubling from Ca dx_min (the
// paper's eq. 16) and bisected to 4 %. Prints one table row:
//   law NE division NB Ca state dx_min h* h*/(Ca dx_min) evaluations
// Usage: stability_limits CONTROL.json   (the mesh, law, flow, Ca = the first level)
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "app/run_checkpoint.h"
#include "capsule/capsule.h"
#include "control/control_file.h"
#include "geometry/surface.h"
#include "membrane/membrane.h"

using namespace capflow;

namespace {

constexpr int kIterations = 30, kMeasured = 10;
constexpr double kUnstable = 1.02, kRelativeSize = 1e-7;

Eigen::Matrix3Xd rk4_step(const capsule::Capsule& cap, const Eigen::Matrix3Xd& x, double ca,
                          double h) {
  const Eigen::Matrix3Xd k1 = cap.velocity(x, ca);
  const Eigen::Matrix3Xd k2 = cap.velocity(x + 0.5 * h * k1, ca);
  const Eigen::Matrix3Xd k3 = cap.velocity(x + 0.5 * h * k2, ca);
  const Eigen::Matrix3Xd k4 = cap.velocity(x + h * k3, ca);
  Eigen::Matrix3Xd x1 = x + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  cap.finish_step(&x1);
  return x1;
}

// Growth per step of a perturbation of x under the step map of size h.
double growth(const capsule::Capsule& cap, const Eigen::Matrix3Xd& x, double ca, double h) {
  const Eigen::Matrix3Xd base = rk4_step(cap, x, ca, h);
  std::mt19937 rng(12345);
  std::normal_distribution<double> normal;
  Eigen::Matrix3Xd d(3, x.cols());
  for (Eigen::Index k = 0; k < d.size(); ++k) d.data()[k] = normal(rng);
  const double size = kRelativeSize * x.norm();
  double log_sum = 0;
  for (int it = 0; it < kIterations; ++it) {
    d *= size / d.norm();
    const Eigen::Matrix3Xd next = rk4_step(cap, x + d, ca, h) - base;
    if (!next.allFinite()) return INFINITY;
    if (it >= kIterations - kMeasured) log_sum += std::log(next.norm() / d.norm());
    d = next;
  }
  return std::exp(log_sum / kMeasured);
}

double first_level(const control::CaSchedule& s) {
  if (s.continuation) return s.continuation->from;
  const control::CaSegment& g = s.segments.at(0);
  return g.kind == control::CaSegment::Kind::Hold ? g.ca : g.to;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: stability_limits CONTROL.json\n");
    return 2;
  }
  try {
    const control::ControlOptions o = control::load_control_file(argv[1]).options;
    const auto mesh = control::make_mesh(o.mesh);
    capsule::Capsule cap(*mesh, o.law, o.flow, control::dynamics_options(o));
    Eigen::Matrix3Xd x = cap.positions();
    std::string state = "sphere";
    if (!o.start.from.empty()) {
      const app::RunCheckpoint c = app::read_latest_checkpoint(o.start.from);
      x = capsule::rescale_to_volume(*mesh, geometry::resample_surface(*c.mesh, c.x, *mesh),
                                     cap.initial_volume());
      state = "Ca=" + std::to_string(c.ca).substr(0, 5) + "-state";
    }
    const double ca = first_level(o.ca);
    const double dx = control::min_node_spacing(o.mesh);
    double lo = 0, hi = ca * dx;
    while (growth(cap, x, ca, hi) <= kUnstable) {
      lo = hi;
      hi *= 2;
    }
    if (lo == 0) {
      lo = hi / 2;
      while (growth(cap, x, ca, lo) > kUnstable) {
        hi = lo;
        lo /= 2;
      }
    }
    while (hi - lo > 0.04 * lo) {
      const double mid = 0.5 * (lo + hi);
      (growth(cap, x, ca, mid) > kUnstable ? hi : lo) = mid;
    }
    const double limit = 0.5 * (lo + hi);
    std::printf("%-12s NE=%-2d %-8s NB=%-2d Ca=%-5g %-14s dx_min %.5f  h* %.5f  h*/(Ca dx_min) %.3f"
                "  evaluations %ld\n",
                membrane::to_string(o.law.kind).c_str(), o.mesh.elements,
                control::division_name(o.mesh.division), o.mesh.nb, ca, state.c_str(), dx, limit,
                limit / (ca * dx), cap.velocity_evaluations());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stability_limits: %s\n", e.what());
    return 1;
  }
  return 0;
}
