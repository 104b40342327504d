// Where a run loses volume: from a run directory's newest checkpoint (or a given .ckpt file),
// the volume rate dV/dt / V of the state, split by element, computed two ways:
//   interp  the flux INT u_h . n dS of the nodal velocities' interpolant (what the time stepping
//           actually does to the discrete volume), and
//   direct  the flux of the velocity evaluated directly at the flux quadrature points
//           (u_inf - SL[f]/(8 pi Ca) there; INT SL[f].n dS = 0 for any f, so this is the
//           quadrature error alone).
// Also the largest |u_direct - u_h| per element (the collocation residual between the nodes,
// which the nodes do not see) and the largest nodal |u|.
// Usage: volume_flux RUN_DIR | CHECKPOINT.ckpt
// Used for the volume-conservation notes in docs/validation.md.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "app/simulation.h"
#include "capsule/capsule.h"
#include "control/control_file.h"
#include "control/schedule.h"
#include "geometry/surface.h"
#include "output/checkpoint.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {

std::string newest_checkpoint(const std::string& arg) {
  if (!fs::is_directory(arg)) return arg;
  const std::string best = app::Simulation::latest_checkpoint(arg);
  if (best.empty()) throw std::runtime_error(arg + ": no checkpoint in checkpoints/");
  return best;
}

int run(const std::string& arg) {
  const std::string path = newest_checkpoint(arg);
  const output::Checkpoint ck = output::Checkpoint::read(path);
  const control::ControlOptions opt =
      control::parse_control(ck.text("control"), path + " (stored control)").options;
  const geometry::Mesh mesh(opt.mesh.elements, opt.mesh.nb);
  const long n = mesh.num_local();
  const auto& xv = ck.doubles("x", 3 * n);
  const Eigen::Matrix3Xd x = Eigen::Map<const Eigen::Matrix3Xd>(xv.data(), 3, n);
  const double t = ck.scalar("t");
  control::CaScheduler schedule(opt.ca, opt.steady, 0.0);
  schedule.restore(ck.doubles("schedule"));
  const double ca = schedule.ca(t);

  const capsule::Capsule cap(mesh, opt.law, opt.flow, control::dynamics_options(opt));
  const Eigen::Matrix3Xd u = cap.velocity(x, ca);
  const Eigen::Matrix3Xd f = cap.traction(x);
  const int nq = mesh.nb() + 4;  // as capsule::enclosed_volume
  const geometry::QuadratureSurface q = geometry::sample_gauss(mesh, x, nq);
  const stokes::BoundaryOperators ops(mesh);
  const Eigen::Matrix3Xd sl = ops.single_layer_at(x, f, q.x);
  const Eigen::Matrix3Xd ud =
      Eigen::Matrix3Xd(cap.flow().gradient * q.x) - sl / (8.0 * M_PI * ca);
  const Eigen::MatrixXd uh = geometry::to_gauss(mesh, u, q.interp);
  const double v = capsule::enclosed_volume(mesh, x);

  std::printf("%s: NE=%d NB=%d t=%.4f Ca=%.4g, V=%.10f (V0 drift %.2e)\n", path.c_str(),
              mesh.ne(), mesh.nb(), t, ca, v, v / cap.initial_volume() - 1.0);
  std::printf("elem  centre node               flux/V interp  flux/V direct  max|u_direct-u_h| at\n");
  double total_h = 0, total_d = 0;
  for (int e = 0; e < mesh.ne(); ++e) {
    double fh = 0, fd = 0, worst = 0;
    long at = e * nq * nq;
    for (long k = e * nq * nq; k < (e + 1) * nq * nq; ++k) {
      fh += uh.col(k).dot(q.n.col(k)) * q.w[k];
      fd += ud.col(k).dot(q.n.col(k)) * q.w[k];
      const double d = (uh.col(k) - ud.col(k)).norm();
      if (d > worst) worst = d, at = k;
    }
    total_h += fh;
    total_d += fd;
    const Eigen::Vector3d c = x.col(mesh.local(e, mesh.nb() / 2, mesh.nb() / 2));
    std::printf("%4d  (%+.2f %+.2f %+.2f)  %+.3e     %+.3e      %.2e (%+.2f %+.2f %+.2f)\n", e, c[0],
                c[1], c[2], fh / v, fd / v, worst, q.x(0, at), q.x(1, at), q.x(2, at));
  }
  std::printf("total dV/dt / V: interp %+.3e  direct %+.3e;  max nodal |u| %.2e\n", total_h / v,
              total_d / v, u.colwise().norm().maxCoeff());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s RUN_DIR | CHECKPOINT.ckpt\n", argv[0]);
    return 2;
  }
  try {
    return run(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "volume_flux: %s\n", e.what());
    return 1;
  }
}
