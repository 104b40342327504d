// Accuracy and cost of quadrature settings for the single layer SL[f] on a capsule state:
// from a run directory's newest checkpoint (or a .ckpt file), the membrane traction f of the
// state and SL[f] at every node, for each variant against a reference with every order of the
// default rules tripled (its own accuracy: --check-ref K compares it with the defaults x K).
// Error = max over nodes |SL - SL_ref| / max |SL_ref|; time = median of 5 calls on 1 thread.
// Variants: "default", "before" (the defaults before 2026-12-02: plain Gauss on the own rays,
// n_radial nb + 4, near edge nb + 2, one near outer panel of nb points, mid order 2 nb + 4), or
// a comma list of key=value over the defaults, keys: n_edge, n_radial_inner, n_radial,
// own_split, own_grading, n_edge_near, n_radial_near, n_radial_near_out, near_out_panels,
// near_split, near_factor, mid_factor, nq_far, nq_mid.
// Usage: quadrature_study [--check-ref K] RUN_DIR|CKPT VARIANT...
// Used for docs/performance.md ("Own and near radial rules").
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/simulation.h"
#include "capsule/capsule.h"
#include "control/control_file.h"
#include "output/checkpoint.h"

using namespace capflow;

namespace {

stokes::QuadratureOptions variant(const std::string& spec, const geometry::Mesh& mesh) {
  const stokes::QuadratureOptions def = stokes::BoundaryOperators(mesh).options();
  stokes::QuadratureOptions o = def;
  if (spec == "default") return o;
  const int nb = mesh.nb();
  if (spec == "before") {
    o.n_radial_inner = 0;
    o.n_radial = nb + 4;
    o.n_edge_near = def.n_edge_near == 2 * nb ? 2 * nb : nb + 2;
    o.near_out_panels = 1;
    o.n_radial_near_out = nb;
    o.nq_mid = 2 * nb + 4;
    return o;
  }
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("variant item without '=': " + item);
    const std::string k = item.substr(0, eq);
    const double v = std::stod(item.substr(eq + 1));
    const int iv = static_cast<int>(v);
    if (k == "n_edge") o.n_edge = iv;
    else if (k == "n_radial_inner") o.n_radial_inner = iv;
    else if (k == "n_radial") o.n_radial = iv;
    else if (k == "own_split") o.own_split = v;
    else if (k == "own_grading") o.own_grading = v;
    else if (k == "n_edge_near") o.n_edge_near = iv;
    else if (k == "n_radial_near") o.n_radial_near = iv;
    else if (k == "n_radial_near_out") o.n_radial_near_out = iv;
    else if (k == "near_out_panels") o.near_out_panels = iv;
    else if (k == "near_split") o.near_split = v;
    else if (k == "near_factor") o.near_factor = v;
    else if (k == "mid_factor") o.mid_factor = v;
    else if (k == "nq_far") o.nq_far = iv;
    else if (k == "nq_mid") o.nq_mid = iv;
    else throw std::invalid_argument("unknown variant key: " + k);
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
  std::string path = argv[a++];
  if (std::filesystem::is_directory(path)) path = app::Simulation::latest_checkpoint(path);
  if (path.empty()) throw std::runtime_error("no checkpoint found");
  const output::Checkpoint ck = output::Checkpoint::read(path);
  const control::ControlOptions opt =
      control::parse_control(ck.text("control"), path + " (stored control)").options;
  const geometry::Mesh mesh(opt.mesh.elements, opt.mesh.nb);
  const long n = mesh.num_local();
  const auto& xv = ck.doubles("x", 3 * n);
  const Eigen::Matrix3Xd x = Eigen::Map<const Eigen::Matrix3Xd>(xv.data(), 3, n);
  const capsule::Capsule cap(mesh, opt.law, opt.flow, control::dynamics_options(opt));
  const Eigen::Matrix3Xd f = cap.traction(x);
  std::vector<int> targets(n);
  for (int m = 0; m < n; ++m) targets[m] = m;
  const stokes::QuadratureOptions def = stokes::BoundaryOperators(mesh).options();
  Eigen::Matrix3Xd ref;
  stokes::BoundaryOperators(mesh, stokes::scale_orders(def, {3, 3, 3})).single_layer(x, f, targets, ref);
  const double scale = ref.colwise().norm().maxCoeff();
  std::printf("%s: NE=%d NB=%d t=%.3f, %ld nodes, max|SL| %.3f\n", path.c_str(), mesh.ne(),
              mesh.nb(), ck.scalar("t"), n, scale);
  if (check_ref > 0) {
    Eigen::Matrix3Xd ref2;
    stokes::BoundaryOperators(mesh, stokes::scale_orders(def, {check_ref, check_ref, check_ref}))
        .single_layer(x, f, targets, ref2);
    std::printf("reference (defaults x3) against defaults x%g: %.2e\n", check_ref,
                (ref2 - ref).colwise().norm().maxCoeff() / scale);
  }
  omp_set_num_threads(1);
  for (; a < argc; ++a) {
    const stokes::BoundaryOperators op(mesh, variant(argv[a], mesh));
    Eigen::Matrix3Xd v;
    std::vector<double> ms;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      op.single_layer(x, f, targets, v);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(ms.begin(), ms.begin() + 2, ms.end());
    Eigen::Index w = 0;
    const double err = (v - ref).colwise().norm().maxCoeff(&w) / scale;
    const int nb2 = mesh.nb() * mesh.nb(), e = static_cast<int>(w) / nb2, loc = static_cast<int>(w) % nb2;
    const stokes::OperatorStats& s = op.last_stats();
    std::printf("%-40s error %.2e at element %d node (%d,%d) x=(%+.2f %+.2f %+.2f); %.1f ms; points own/near/far %ld/%ld/%ld\n",
                argv[a], err, e, loc % mesh.nb(), loc / mesh.nb(), x(0, w), x(1, w), x(2, w),
                ms[2], s.own_pairs, s.near_pairs, s.far_pairs);
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
