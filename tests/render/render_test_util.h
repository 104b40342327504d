// Helpers shared by the renderer tests: analytic snapshots and backend availability.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "render/context.h"
#include "render/snapshot.h"

namespace capflow::render::testing {

inline Snapshot shape_snapshot(int ne, int nb, const geometry::PointMap& map,
                               double (*field)(double, double, double) = nullptr) {
  geometry::Mesh mesh(ne, nb);
  const auto x = geometry::map_points(mesh.reference(), map);
  Snapshot s;
  s.ne = ne;
  s.nb = nb;
  const int n = mesh.num_local();
  s.x.resize(3 * static_cast<size_t>(n));
  s.tau1.resize(n);
  s.tau2.resize(n);
  for (int k = 0; k < n; ++k) {
    for (int d = 0; d < 3; ++d) s.x[3 * k + d] = x(d, k);
    const double f = field ? field(x(0, k), x(1, k), x(2, k)) : 0.0;
    s.tau1[k] = s.tau2[k] = f;
  }
  s.time = 1.25;
  s.ca = 0.1;
  s.law = "neo-Hookean";
  return s;
}

// Skips the test, saying which backend this machine lacks, when it cannot create a context.
inline void require_backend(Backend b) {
  try {
    GlContext::create(b);
  } catch (const std::exception& e) {
    GTEST_SKIP() << "this machine lacks the " << backend_name(b) << " backend: " << e.what();
  }
}

}  // namespace capflow::render::testing
