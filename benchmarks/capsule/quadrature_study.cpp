// Accuracy and cost of quadrature settings for the single layer SL[f] on a capsule state:
// from a run directory's newest checkpoint (or a .ckpt file), the membrane traction f of the
// state and SL[f] at every node, for each variant against a reference with every order of the
// default rules tripled (its own accuracy: --check-ref K compares it with the defaults x K).
// Error = max over nodes |SL - SL_ref| / max |SL_ref|; time = median of 5 calls on 1 thread.
// Variants: "default", "before" (the defaults before 2026-12-02: plain Gauss on the own rays,
// n_radial nb + 4, near edge nb + 2, one near outer panel of nb points, mid order 2 nb + 4), or
// a comma list of key=value over the defaults, keys: n_edge, own_edge_base, own_edge_slope,
// n_radial_inner, n_radial, own_split, own_grading, n_edge_near, n_radial_near, n_radial_near_out,
// near_out_panels, near_split, near_factor, mid_factor, nq_far, nq_mid, single_near_factor,
// single_nq_mid, single_mid_split. Usage: quadrature_study [--check-ref K] RUN_DIR|CKPT VARIANT...
// Used for docs/performance.md ("Own and near radial rules", "Own edge orders by the sinh
// range", "Accuracy").
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/run_checkpoint.h"
#include "capsule/capsule.h"
#include "control/control_file.h"

using namespace capflow;

namespace {

stokes::QuadratureOptions variant(const std::string& spec, const stokes::QuadratureOptions& def,
                                  int nb) {
  stokes::QuadratureOptions o = def;
  if (spec == "default") return o;
  if (spec == "before") {
    o.own_edge_base = 0.0;
    o.n_radial_inner = 0;
    o.n_radial = nb + 4;
    o.n_edge_near = def.n_edge_near == 2 * nb ? 2 * nb : nb + 2;
    o.near_out_panels = 1;
    o.n_radial_near_out = nb;
    o.nq_mid = 2 * nb + 4;
    return o;
  }
  using Q = stokes::QuadratureOptions;
  static const std::map<std::string, int Q::*> ints = {{"n_edge", &Q::n_edge},
                                                       {"n_radial_inner", &Q::n_radial_inner},
                                                       {"n_radial", &Q::n_radial},
                                                       {"n_edge_near", &Q::n_edge_near},
                                                       {"n_radial_near", &Q::n_radial_near},
                                                       {"n_radial_near_out", &Q::n_radial_near_out},
                                                       {"near_out_panels", &Q::near_out_panels},
                                                       {"nq_far", &Q::nq_far},
                                                       {"nq_mid", &Q::nq_mid},
                                                       {"single_nq_mid", &Q::single_nq_mid}};
  static const std::map<std::string, double Q::*> reals = {
      {"own_split", &Q::own_split},
      {"own_grading", &Q::own_grading},
      {"own_edge_base", &Q::own_edge_base},
      {"own_edge_slope", &Q::own_edge_slope},
      {"near_split", &Q::near_split},
      {"near_factor", &Q::near_factor},
      {"single_near_factor", &Q::single_near_factor},
      {"single_mid_split", &Q::single_mid_split},
      {"mid_factor", &Q::mid_factor}};
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("variant item without '=': " + item);
    const std::string k = item.substr(0, eq);
    const double v = std::stod(item.substr(eq + 1));
    if (const auto i = ints.find(k); i != ints.end())
      o.*(i->second) = static_cast<int>(v);
    else if (const auto r = reals.find(k); r != reals.end())
      o.*(r->second) = v;
    else
      throw std::invalid_argument("unknown variant key: " + k);
  }
  return o;
}

int run(int argc, char** argv) {
  int a = 1;
  double check_ref = 0;
  if (a < argc && std::string(argv[a]) == "--check-ref" && a + 1 < argc) {
    check_ref = std::atof(argv[a + 1]);
    a += 2;
  }
  if (argc - a < 1) {
    std::fprintf(stderr, "usage: %s [--check-ref K] RUN_DIR|CKPT VARIANT...\n", argv[0]);
    return 2;
  }
  const app::RunCheckpoint state = app::read_latest_checkpoint(argv[a++]);
  const geometry::Mesh& mesh = *state.mesh;
  const Eigen::Matrix3Xd& x = state.x;
  const long n = mesh.num_local();
  const capsule::Capsule cap(mesh, state.options.law, state.options.flow,
                             control::dynamics_options(state.options));
  const Eigen::Matrix3Xd f = cap.traction(x);
  std::vector<int> targets(n);
  for (int m = 0; m < n; ++m) targets[m] = m;
  const stokes::QuadratureOptions def = stokes::resolve_defaults(mesh, {});
  Eigen::Matrix3Xd ref;
  stokes::BoundaryOperators(mesh, stokes::scale_orders(def, {3, 3, 3}))
      .single_layer(x, f, targets, ref);
  const double scale = ref.colwise().norm().maxCoeff();
  std::printf("%s: NE=%d NB=%d t=%.3f, %ld nodes, max|SL| %.3f\n", state.path.c_str(), mesh.ne(),
              mesh.nb(), state.t, n, scale);
  if (check_ref > 0) {
    Eigen::Matrix3Xd ref2;
    stokes::BoundaryOperators(mesh, stokes::scale_orders(def, {check_ref, check_ref, check_ref}))
        .single_layer(x, f, targets, ref2);
    std::printf("reference (defaults x3) against defaults x%g: %.2e\n", check_ref,
                (ref2 - ref).colwise().norm().maxCoeff() / scale);
  }
  omp_set_num_threads(1);
  for (; a < argc; ++a) {
    const stokes::BoundaryOperators op(mesh, variant(argv[a], def, mesh.nb()));
    Eigen::Matrix3Xd v;
    std::vector<double> ms;
    stokes::OperatorStats s;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      op.single_layer(x, f, targets, v, &s);
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(ms.begin(), ms.begin() + 2, ms.end());
    Eigen::Index w = 0;
    const double err = (v - ref).colwise().norm().maxCoeff(&w) / scale;
    const int nb2 = mesh.nb() * mesh.nb(), e = static_cast<int>(w) / nb2,
              loc = static_cast<int>(w) % nb2;
    std::printf(
        "%-40s error %.2e at element %d node (%d,%d) x=(%+.2f %+.2f %+.2f); %.1f ms; points "
        "own/near/far %ld/%ld/%ld\n",
        argv[a], err, e, loc % mesh.nb(), loc / mesh.nb(), x(0, w), x(1, w), x(2, w), ms[2],
        s.own_pairs, s.near_pairs, s.far_pairs);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "quadrature_study: %s\n", e.what());
    return 1;
  }
}
