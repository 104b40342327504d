// Study program (Milestone 8, Deliver 2): the stability limit of fixed RK4 steps, measured.
//
// For the state of a control file (the sphere at rest, or the shape of a checkpoint given with
// start.from, e.g. a steady state of capflow steady) the growth per step of small perturbations
// under the step map Phi_h (classical RK4 at the control file's Ca, then the capsule's
// end-of-step smoothing, as `capflow run` steps with a fixed time.dt): rho(h), the spectral
// radius of dPhi_h/dx, estimated by 40 Arnoldi steps (difference quotients). The limit h* is
// where rho crosses 1 + 2h (above the flow's own growth, see unstable()): bracketed by doubling
// from Ca dx_min (the paper's eq. 16) and bisected to 4 %. Prints one table row:
//   law NE division NB Ca state dx_min h* h*/(Ca dx_min) evaluations
// Usage: stability_limits CONTROL.json   (the mesh, law, flow, Ca = the first level)
#include <Eigen/Eigenvalues>
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

constexpr int kKrylov = 40;
constexpr double kRelativeSize = 1e-7;
// Growth per step that counts as unstable: above the physical growth of the flow (a translation
// along the extension axis grows as e^{G t}: 1 + h per step), 1 + 2h.
double unstable(double h) {
  return 1 + 2 * h;
}

Eigen::Matrix3Xd rk4_step(const capsule::Capsule& cap, const Eigen::Matrix3Xd& x, double ca,
                          double h) {
  return cap.rk4_step(x, 0.0, h, [ca](double) { return ca; });
}

// The spectral radius of the step map's linearisation M = dPhi_h/dx at x: the largest modulus
// of the Ritz values of an Arnoldi process of kKrylov steps on M (products by difference
// quotients of size 1e-7 of the shape), started from a random vector.
double growth(const capsule::Capsule& cap, const Eigen::Matrix3Xd& x, double ca, double h) {
  const Eigen::Matrix3Xd base = rk4_step(cap, x, ca, h);
  const Eigen::Index n = x.size();
  const double eps = kRelativeSize * x.norm();
  Eigen::MatrixXd V(n, kKrylov + 1);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(kKrylov + 1, kKrylov);
  std::mt19937 rng(12345);
  std::normal_distribution<double> normal;
  for (Eigen::Index k = 0; k < n; ++k) V(k, 0) = normal(rng);
  V.col(0).normalize();
  int m = kKrylov;
  for (int j = 0; j < kKrylov; ++j) {
    const Eigen::Map<const Eigen::Matrix3Xd> v(V.col(j).data(), 3, x.cols());
    const Eigen::Matrix3Xd mv = (rk4_step(cap, x + eps * v, ca, h) - base) / eps;
    if (!mv.allFinite()) return INFINITY;
    Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(mv.data(), n);
    for (int i = 0; i <= j; ++i) {
      H(i, j) = V.col(i).dot(w);
      w -= H(i, j) * V.col(i);
    }
    H(j + 1, j) = w.norm();
    if (H(j + 1, j) < 1e-12) {
      m = j + 1;
      break;
    }
    V.col(j + 1) = w / H(j + 1, j);
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> es(H.topLeftCorner(m, m), false);
  return es.eigenvalues().cwiseAbs().maxCoeff();
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
    while (growth(cap, x, ca, hi) <= unstable(hi)) {
      lo = hi;
      hi *= 2;
    }
    if (lo == 0) {
      lo = hi / 2;
      while (growth(cap, x, ca, lo) > unstable(lo)) {
        hi = lo;
        lo /= 2;
      }
    }
    while (hi - lo > 0.04 * lo) {
      const double mid = 0.5 * (lo + hi);
      (growth(cap, x, ca, mid) > unstable(mid) ? hi : lo) = mid;
    }
    const double limit = 0.5 * (lo + hi);
    std::printf(
        "%-12s NE=%-2d %-8s NB=%-2d Ca=%-5g %-14s dx_min %.5f  h* %.5f  h*/(Ca dx_min) %.3f"
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
