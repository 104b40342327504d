// capflow steady's solvers on their own (app/level_solver.h, app/branch_follower.h): no run
// directory, no log - only the hooks. A level's root is checked against the capsule's own
// velocity (at a steady shape in a pure straining flow every node is at rest, up to the
// discretisation's volume leak), a stop ends a
// solve at once, and the branch follower's states lie on the branch (each a root, D growing
// with Ca up to the range's end).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/branch_follower.h"
#include "app/cpu_budget.h"
#include "app/level_solver.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "diagnostics/diagnostics.h"

using namespace capflow;
using app::BranchFollower;
using app::Grid;
using app::LevelSolver;

namespace {

control::ControlOptions small_options() {
  return control::parse_control(R"({"capsule": {"law": "skalak", "C": 1},
      "mesh": {"elements": 6, "nb": 6}, "ca": 0.3, "numerics": {"threads": 1}})")
      .options;
}

double largest_node_speed(Grid& g, double ca) {
  return g.cap->velocity(g.x, ca).colwise().norm().maxCoeff();
}

double deformation(const Grid& g) {
  return diagnostics::measure_shape(*g.mesh, g.x, diagnostics::ShapeOptions{}).D;
}

}  // namespace

TEST(LevelSolver, ARootIsAShapeAtRest) {
  const control::ControlOptions o = small_options();
  Grid fine = app::make_grid(o);
  std::vector<std::string> said;
  LevelSolver::Hooks hooks;
  hooks.say = [&](const std::string& s) { said.push_back(s); };
  LevelSolver solver(o, fine, hooks);
  const LevelSolver::Result r = solver.solve(0.3, true);
  ASSERT_TRUE(r.converged) << r.failure;
  EXPECT_LE(r.solution.residual, o.steady.solve_tolerance);
  EXPECT_GT(r.newton, 0);
  EXPECT_GT(r.evaluations, 0);
  EXPECT_GT(solver.time(), 0.0);  // the approach marched
  // independently of the step map: the capsule's velocity at the root is the discretisation's
  // volume leak and the smoothing's floor (~1e-4 at NB=6), 1000x below the sphere's
  EXPECT_LT(largest_node_speed(fine, 0.3), 1e-3);
  // the solution's speed is the largest velocity component: between |u|/sqrt(3) and |u|
  EXPECT_GE(largest_node_speed(fine, 0.3), r.solution.speed * (1 - 1e-12));
  EXPECT_LE(largest_node_speed(fine, 0.3), std::sqrt(3.0) * r.solution.speed);
  // and the sphere at rest is no root at this Ca
  Grid rest = app::make_grid(o);
  EXPECT_GT(largest_node_speed(rest, 0.3), 0.1);
  EXPECT_FALSE(said.empty());
}

// Below Ca ~ 0.15 in planar extension a membrane without bending stiffness is compressed and
// wrinkles at the grid scale: at Ca = 0.05 (Skalak C = 1, NE = 6, NB = 8) Newton either fails or
// lands on a root with node-to-node oscillation above the time steps' limit. With Eb = 0.01 the
// same level has a smooth root, still with compressive tension.
TEST(LevelSolver, BendingResolvesALowCaRootThatWrinklesWithout) {
  app::set_solver_threads(1);  // as capflow steady does with numerics.threads
  const auto options = [](double eb) {
    return control::parse_control(R"({"capsule": {"law": "skalak", "C": 1, "bending": {"modulus": )" +
                                  std::to_string(eb) + R"(}}, "mesh": {"elements": 6, "nb": 8,
        "division": "diagonal"}, "ca": 0.05, "numerics": {"threads": 1}})")
        .options;
  };
  const double limit = capsule::HealthOptions{}.oscillation_fail;
  {
    const control::ControlOptions o = options(0.01);
    Grid g = app::make_grid(o);
    LevelSolver solver(o, g, LevelSolver::Hooks{});
    const LevelSolver::Result r = solver.solve(0.05, true);
    ASSERT_TRUE(r.converged) << r.failure;
    EXPECT_LE(r.solution.residual, o.steady.solve_tolerance);
    const double a = capsule::HealthMonitor(*g.mesh, g.x).oscillation_indicator(g.x);
    std::printf("Eb = 0.01: %d Newton iterations, oscillation %.2e, D = %.4f\n", r.newton, a,
                deformation(g));
    EXPECT_LT(a, limit / 4);
    EXPECT_LT(largest_node_speed(g, 0.05), 1e-3);
  }
  {
    const control::ControlOptions o = options(0);
    Grid g = app::make_grid(o);
    LevelSolver solver(o, g, LevelSolver::Hooks{});
    const LevelSolver::Result r = solver.solve(0.05, true);
    const double a = capsule::HealthMonitor(*g.mesh, g.x).oscillation_indicator(g.x);
    std::printf("Eb = 0: converged %d, oscillation %.2e\n", r.converged, a);
    EXPECT_TRUE(!r.converged || a > limit) << "a membrane without bending resolves Ca = 0.05";
  }
}

// Small-deformation theory with bending (docs/validation.md, sec. 5, with the bending load added
// to the normal balance): a normal displacement W Y (Y = n.E.n, l = 2) carries the bending load
// F2 W Y n, F2 = 24 Eb (Helfrich, c0 = 0) or 16 Eb (bending about the sphere), and no tangential
// load, so with A = 2W - 6P
//   normal      2 Ks A + F2 W = 5 Ca,   tangential  Ks A - 4P = -5 Ca / 2,
//   A = Ca (5 - 15 F2 / 8) / (2 Ks + F2 (2 + 3 Ks) / 4),   W = A (1/2 + 3 Ks / 4) + 15 Ca / 8,
// which is (5/4) Ca (3 + 1/Ks) at F2 = 0. Planar extension: D = W. Skalak C = 1 (Ks = 3),
// Ca = 0.01, NE 6 NB 8; the O(Ca^2) terms are -0.3 % without bending (sec. 5).
TEST(LevelSolver, SmallDeformationWithBendingMatchesLinearTheory) {
  app::set_solver_threads(1);  // as capflow steady does with numerics.threads
  struct Case {
    double eb;
    const char* model;
    double f2_per_eb;
  };
  for (const Case& c : {Case{0.01, "helfrich", 24}, Case{0.05, "helfrich", 24},
                        Case{0.05, "reference", 16}}) {
    const control::ControlOptions o =
        control::parse_control(R"({"capsule": {"law": "skalak", "C": 1, "bending": {"modulus": )" +
                               std::to_string(c.eb) + R"(, "model": ")" + c.model +
                               R"("}}, "mesh": {"elements": 6, "nb": 8, "division": "diagonal"},
            "ca": 0.01, "numerics": {"threads": 1}})")
            .options;
    Grid g = app::make_grid(o);
    LevelSolver solver(o, g, LevelSolver::Hooks{});
    const LevelSolver::Result r = solver.solve(0.01, true);
    ASSERT_TRUE(r.converged) << r.failure;
    const double ks = 3, f2 = c.f2_per_eb * c.eb, ca = 0.01;
    const double a = ca * (5 - 15 * f2 / 8) / (2 * ks + f2 * (2 + 3 * ks) / 4);
    const double w = a * (0.5 + 0.75 * ks) + 15 * ca / 8;
    const double d = deformation(g);
    std::printf("Eb = %g (%s): D / Ca = %.5f, theory %.5f, relative difference %+.2e\n", c.eb,
                c.model, d / ca, w / ca, d / w - 1);
    EXPECT_NEAR(d / w, 1, 0.01) << c.eb << " " << c.model;
  }
}

TEST(LevelSolver, AStopEndsASolveAtOnce) {
  const control::ControlOptions o = small_options();
  Grid fine = app::make_grid(o);
  std::atomic<bool> stop{true};
  LevelSolver::Hooks hooks;
  hooks.stop = &stop;
  LevelSolver solver(o, fine, hooks);
  const LevelSolver::Result r = solver.solve(0.3, true);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(solver.stopped());
  EXPECT_EQ(solver.steps(), 0);
}

TEST(LevelSolver, LiveEditsReachItBetweenSteps) {
  control::ControlOptions o = small_options();
  Grid fine = app::make_grid(o);
  int calls = 0;
  LevelSolver::Hooks hooks;
  hooks.between_steps = [&] {
    ++calls;
    o.steady.solve_tolerance = 1e-9;  // an edit the Newton solve then uses
  };
  LevelSolver solver(o, fine, hooks);
  const LevelSolver::Result r = solver.solve(0.3, true);
  ASSERT_TRUE(r.converged) << r.failure;
  EXPECT_GT(calls, 0);
  EXPECT_LE(r.solution.residual, 1e-9);
}

TEST(BranchFollower, ItsStatesLieOnTheBranch) {
  control::ControlOptions o = small_options();
  Grid fine = app::make_grid(o);
  LevelSolver solver(o, fine, {});
  ASSERT_TRUE(solver.solve(0.2, true).converged);
  control::Continuation c;
  c.from = 0.2;
  c.to = 0.3;
  c.step = 0.05;
  BranchFollower branch(solver, fine, c);
  double last_ca = 0.2, last_d = deformation(fine);
  int states = 0;
  for (;;) {
    const BranchFollower::Step s = branch.advance();
    if (s.status == BranchFollower::Status::Done) break;
    ASSERT_EQ(s.status, BranchFollower::Status::State) << branch.branch().why();
    ASSERT_TRUE(s.k.last.converged);
    const double ca = branch.branch().last().ca;
    EXPECT_GT(ca, last_ca);
    EXPECT_GT(deformation(fine), last_d);  // Skalak C=1 in planar extension: D grows with Ca
    EXPECT_LT(largest_node_speed(fine, ca), 1e-3) << "Ca = " << ca;
    last_ca = ca;
    last_d = deformation(fine);
    ASSERT_LT(++states, 20);
  }
  EXPECT_NEAR(last_ca, 0.3, 1e-9);
  EXPECT_GE(states, 2);
}
