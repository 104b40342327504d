// Viscosity ratio lambda in planar extension, a pure straining flow: a steady capsule's membrane
// is at rest, u = 0 on the surface, so the double-layer term of the boundary integral equation
// vanishes and the steady shapes do not depend on lambda (method.md section 9); the path to them
// does (a more viscous interior deforms more slowly). capflow steady at lambda = 0.2 and 5
// against lambda = 1 (Skalak C = 1, Ca = 0.45, NE = 6 NB = 8).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "app/simulation.h"
#include "app/steady_run.h"
#include "control/control_file.h"
#include "test_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {
struct Steady {
  double D, L, S, W;
  long evaluations;
};
Steady steady_at(double lambda) {
  const fs::path d = test::fresh_dir("steady_lambda");
  control::ParsedControl p = control::parse_control(
      R"({"capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 8},
          "flow": {"type": "planar-extension"}, "ca": 0.45, "output": {"mp4": false}})");
  p.options.output.dir = d.string();
  p.options.viscosity_ratio = lambda;
  const app::SteadySummary s = app::run_steady(p.options, false);
  EXPECT_EQ(s.states, 1) << "lambda " << lambda << ": " << s.failure;
  const Steady r{test::csv_column(d / "steady.csv", "D").at(0),
                 test::csv_column(d / "steady.csv", "L").at(0),
                 test::csv_column(d / "steady.csv", "S").at(0),
                 test::csv_column(d / "steady.csv", "W").at(0), s.evaluations};
  fs::remove_all(d);
  return r;
}
}  // namespace

TEST(ViscosityRatio, SteadyShapesInPlanarExtensionDoNotDependOnIt) {
  const Steady one = steady_at(1.0);
  for (double lambda : {0.2, 5.0}) {
    const Steady s = steady_at(lambda);
    std::printf("lambda %g: D %.7f L %.7f S %.7f W %.7f (%ld evaluations); lambda 1: D %.7f\n",
                lambda, s.D, s.L, s.S, s.W, s.evaluations, one.D);
    // capflow steady's residual (1e-7 on the map step) leaves the shapes within ~1e-5
    EXPECT_NEAR(s.D, one.D, 2e-5) << lambda;
    EXPECT_NEAR(s.L, one.L, 2e-5) << lambda;
    EXPECT_NEAR(s.S, one.S, 2e-5) << lambda;
    EXPECT_NEAR(s.W, one.W, 2e-5) << lambda;
  }
}
