#include "control/stability.h"

#include <algorithm>
#include <cmath>

#include "control/control_file.h"

namespace capflow::control {

namespace {

struct Fit {
  double p, b;  // h* = c dx_min^p Ca / (1 + b Ca)
  // c for NE=6 diagonal, NE=6 cube, NE=10 box, NE=10 cube, NE=14 cube
  double c6_diagonal, c6_cube, c10_box, c10_cube, c14_cube;
};

// fit_stability.py on the rows of stability_limits.sh (docs/performance.md).
constexpr Fit kSteadySkalak{1.127, 1.57, 1.3335, 1.3755, 2.1090, 2.3439, 3.0178};
constexpr Fit kSphere{1.076, 0.0, 1.4087, 1.4799, 1.9527, 2.2937, 2.3256};

double coefficient(const Fit& f, const MeshOptions& m) {
  using geometry::Division;
  if (m.elements == 6) return m.division == Division::Diagonal ? f.c6_diagonal : f.c6_cube;
  if (m.elements == 10) return m.division == Division::Box ? f.c10_box : f.c10_cube;
  // NE=14: only the cube was measured; the box (1:3:1) uses the cube's coefficient (not
  // measured).
  return f.c14_cube;
}

double limit(const Fit& f, const MeshOptions& m, double ca) {
  return coefficient(f, m) * std::pow(min_node_spacing(m), f.p) * ca / (1 + f.b * ca);
}

}  // namespace

double fixed_step_limit(const MeshOptions& mesh, membrane::LawKind law, double ca) {
  const double sphere = limit(kSphere, mesh, ca);
  if (law == membrane::LawKind::NeoHookean) return sphere;
  return std::min(limit(kSteadySkalak, mesh, ca), sphere);
}

}  // namespace capflow::control
