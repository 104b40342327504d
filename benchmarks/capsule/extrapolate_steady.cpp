// A starting state for a run near a steady state that the time stepping approaches slowly:
// from three checkpoints of one run a time Delta apart (same mesh), the one-mode extrapolation
// of capsule/extrapolation.h, written as a checkpoint (the newest input's, with x replaced) that
// `start.from` accepts. Prints the fitted ratio q per interval, the time constant
// tau = -Delta / ln q, the one-mode residual, and the shape of the inputs and of the result.
// The result is NOT a steady state by itself: a run from it (same mesh, law, Ca, dt) must show
// that the dynamics stay there (its steady test); docs/validation.md reports both.
// Usage: extrapolate_steady [--max-residual R] A.ckpt B.ckpt C.ckpt OUT.ckpt
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "capsule/extrapolation.h"
#include "app/run_checkpoint.h"
#include "diagnostics/diagnostics.h"

using namespace capflow;

namespace {

void print_shape(const char* what, double t, const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  const diagnostics::ShapeDiagnostics d = diagnostics::measure_shape(mesh, x);
  std::printf("%-12s t=%-9.4f L %.6f S %.6f W %.6f Lc %.6f Sc %.6f Wc %.6f D %.6f edge curv. %.3f volume %.10f\n",
              what, t, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.edge_curvature, d.volume);
}

int usage() {
  std::fprintf(stderr, "usage: extrapolate_steady [--max-residual R] A.ckpt B.ckpt C.ckpt OUT.ckpt\n"
                       "  three checkpoints of one run, equally spaced in time (A oldest)\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  double max_residual = 0.05;
  int i = 1;
  if (i < argc && std::string(argv[i]) == "--max-residual") {
    if (i + 1 >= argc) return usage();
    char* end = nullptr;
    max_residual = std::strtod(argv[i + 1], &end);
    if (*end != '\0' || !(max_residual > 0 && max_residual < 1)) {
      std::fprintf(stderr, "extrapolate_steady: --max-residual must be a number in (0, 1), got '%s'\n",
                   argv[i + 1]);
      return 2;
    }
    i += 2;
  }
  if (argc - i != 4) return usage();
  try {
    const app::RunCheckpoint a = app::read_run_checkpoint(argv[i]);
    const app::RunCheckpoint b = app::read_run_checkpoint(argv[i + 1]);
    const app::RunCheckpoint c = app::read_run_checkpoint(argv[i + 2]);
    const std::string out = argv[i + 3];
    for (const auto* s : {&b, &c})
      if (s->options.mesh.elements != a.options.mesh.elements || s->options.mesh.nb != a.options.mesh.nb)
        throw std::runtime_error(s->path + ": another mesh than " + a.path);
    const double ta = a.t, tb = b.t, tc = c.t;
    const double delta = tb - ta;
    if (!(delta > 0) || std::abs((tc - tb) - delta) > 1e-6 * std::max(1.0, delta))
      throw std::runtime_error("the checkpoints must be in time order and equally spaced: t = " +
                               std::to_string(ta) + ", " + std::to_string(tb) + ", " + std::to_string(tc));
    const geometry::Mesh& mesh = *c.mesh;
    print_shape("A", ta, mesh, a.x);
    print_shape("B", tb, mesh, b.x);
    print_shape("C", tc, mesh, c.x);
    const capsule::OneModeExtrapolation r = capsule::extrapolate_one_mode(a.x, b.x, c.x, max_residual);
    const double tau = -delta / std::log(r.q);
    std::printf("one mode: q = %.6f per %.4g time units (tau = %.3f), residual %.3e, C + %.4f (C - B)\n",
                r.q, delta, tau, r.residual, r.factor);
    print_shape("extrapolated", tc, mesh, r.x);

    app::RunCheckpoint ck = c;
    ck.x = r.x;
    std::ostringstream note;
    note << "one-mode extrapolation (benchmarks/capsule/extrapolate_steady) of " << a.path << " (t=" << ta
         << "), " << b.path << " (t=" << tb << "), " << c.path << " (t=" << tc << "): q=" << r.q
         << ", tau=" << tau << ", residual=" << r.residual;
    ck.note = note.str();
    app::write_run_checkpoint(ck, out);
    std::printf("wrote %s (t = %.4f, the time of C; start a run from it with start.from)\n", out.c_str(), tc);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "extrapolate_steady: %s\n", e.what());
    return 1;
  }
}
