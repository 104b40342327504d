// Where a run loses volume: from a run directory's newest checkpoint (or a given .ckpt file),
// the volume rate dV/dt / V of the state, split by element, computed two ways:
//   interp  the flux INT u_h . n dS of the nodal velocities' interpolant (what the time stepping
//           actually does to the discrete volume), and
//   direct  the flux of the velocity evaluated directly at the flux quadrature points
//           (u_inf - SL[f]/(8 pi Ca) there, with every quadrature order tripled; INT SL[f].n dS
//           = 0 for any f, so this is the remaining quadrature error alone).
// Also the largest |u_direct - u_h| per element (the collocation residual between the nodes,
// which the nodes do not see), the largest nodal |u|, the error of the nodal velocity of the
// run's rules against the x3 reference, and the largest angle between the normals of
// neighbouring nodes (the tip resolution the health check warns about).
// Usage: volume_flux [--quad-scale K] [--far-scale K] [--own-scale K] [--near-scale K]
//                    [--mid-scale K] [--no-traction-smoothing] RUN_DIR | CHECKPOINT.ckpt
// (--quad-scale: every quadrature order of the velocity times K, to tell quadrature error from
// the discretisation of the fields).
// Used for the volume-conservation notes in docs/validation.md.
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "app/run_checkpoint.h"
#include "capsule/capsule.h"
#include "control/control_file.h"
#include "control/schedule.h"
#include "geometry/surface.h"
#include "output/checkpoint.h"

using namespace capflow;

namespace {

constexpr double kRefScale = 3.0;

struct Variant {
  stokes::OrderScales quad;  // of the velocity the state is checked with
  bool smooth_traction = true;
};

int run(const std::string& arg, const Variant& var) {
  const app::RunCheckpoint state = app::read_latest_checkpoint(arg);
  const std::string& path = state.path;
  const control::ControlOptions& opt = state.options;
  const geometry::Mesh& mesh = *state.mesh;
  const Eigen::Matrix3Xd& x = state.x;
  const double t = state.t;
  const double ca = state.ca;

  capsule::DynamicsOptions dyn = control::dynamics_options(opt);
  const stokes::QuadratureOptions run_quadrature = capsule::quadrature_rules(mesh, dyn);
  dyn.quadrature_scale = 1.0;
  dyn.smooth_traction = var.smooth_traction;
  dyn.quadrature = stokes::scale_orders(run_quadrature, var.quad);
  const capsule::Capsule cap(mesh, opt.law, opt.flow, dyn);
  const Eigen::Matrix3Xd u = cap.velocity(x, ca);
  const Eigen::Matrix3Xd f = cap.traction(x);
  const int nq = mesh.nb() + 4;  // as capsule::enclosed_volume
  const geometry::QuadratureSurface q = geometry::sample_gauss(mesh, x, nq);
  // The direct velocity between the nodes is evaluated with every quadrature order tripled: the
  // default near rule at on-surface points (h = 0) is cruder than the own-element rules the
  // nodes use (3e-3 off at the nodes of fig. 2b at t=10; 2e-9 at x3, measured with --quad-scale).
  const stokes::BoundaryOperators ref(
      mesh, stokes::scale_orders(run_quadrature, {kRefScale, kRefScale, kRefScale}));
  const Eigen::Matrix3Xd sl = ref.single_layer_at(x, f, q.x);
  const Eigen::Matrix3Xd ud =
      Eigen::Matrix3Xd(cap.flow().gradient * q.x) - sl / (8.0 * M_PI * ca);
  const Eigen::MatrixXd uh = geometry::to_gauss(mesh, u, q.interp);
  // the run's operator at the nodes against the reference there: the error of the nodal velocity
  const Eigen::Matrix3Xd sl_nodes = ref.single_layer_at(x, f, x);
  const Eigen::Matrix3Xd u_ref = Eigen::Matrix3Xd(cap.flow().gradient * x) - sl_nodes / (8.0 * M_PI * ca);
  Eigen::Index worst_node = 0;
  const double nodal_error = (u_ref - u).colwise().norm().maxCoeff(&worst_node);
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
  std::printf("nodal velocity against the x%.0f reference: max |u - u_ref| %.2e at (%+.2f %+.2f %+.2f)\n",
              kRefScale, nodal_error, x(0, worst_node), x(1, worst_node), x(2, worst_node));
  int m = 0;
  const double turn = geometry::max_normal_turning(mesh, geometry::compute_geometry(mesh, x).n, &m);
  std::printf("largest normal turning between neighbouring nodes: %.3f rad at (%+.3f %+.3f %+.3f)\n",
              turn, x(0, m), x(1, m), x(2, m));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Variant var;
  std::string target;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    double* scale = a == "--far-scale" ? &var.quad.far
                    : a == "--own-scale" ? &var.quad.own
                    : a == "--near-scale" ? &var.quad.near
                    : a == "--mid-scale"  ? &var.quad.mid
                                          : nullptr;
    if ((scale || a == "--quad-scale") && i + 1 < argc) {
      const double k = std::atof(argv[++i]);
      if (!(k >= 0.5 && k <= 4.0)) {
        std::fprintf(stderr, "volume_flux: %s must be in [0.5, 4], got %s\n", a.c_str(), argv[i]);
        return 2;
      }
      if (scale)
        *scale = k;
      else
        var.quad = stokes::OrderScales{k, k, k};
    } else if (a == "--no-traction-smoothing") {
      var.smooth_traction = false;
    } else if (target.empty() && a[0] != '-') {
      target = a;
    } else {
      target.clear();
      break;
    }
  }
  if (target.empty()) {
    std::fprintf(stderr,
                 "usage: %s [--quad-scale K] [--far-scale K] [--own-scale K] [--near-scale K]\n"
                 "          [--mid-scale K] [--no-traction-smoothing] RUN_DIR | CHECKPOINT.ckpt\n"
                 "  --quad-scale K  multiply every quadrature order of the velocity by K (0.5..4);\n"
                 "  --far-scale, --own-scale, --near-scale: only the far (and mid), own or near\n"
                 "  orders; --mid-scale: the mid order apart from the far one\n",
                 argv[0]);
    return 2;
  }
  try {
    return run(target, var);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "volume_flux: %s\n", e.what());
    return 1;
  }
}
