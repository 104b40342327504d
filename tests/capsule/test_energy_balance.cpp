// The energy balance of a capsule run: the membrane is elastic, so its strain energy changes at
// the rate the fluids work on it,
//   dE/dt = INT f.u dS   (f = n.(sigma_out - sigma_in) = -div_s tau, the traction jump, which is
//                         the variation of E per area; u the surface velocity).
// The identity holds for any surface motion; discretely it checks the run's tractions (smoothed
// tangents) against the strain energy of the interpolated surface along the actual trajectory,
// through the time integration and the smoothing of every step. Neo-Hookean capsule in simple
// shear at Ca = 0.6, the case where capflow's steady D lies ~0.02 above published codes
// (docs/validation.md, 15.3 "Against published codes"): E(t) - E(0) against the time integral of
// INT f.u dS, over the first time unit and through the overshoot to the tank-treading state.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "capsule/capsule.h"
#include "geometry/surface.h"
#include "membrane/membrane.h"

using namespace capflow;
using namespace capflow::capsule;

namespace {

// INT f.u dS on the surface x (Gauss quadrature on the interpolated surface, NB + 4 points).
double power(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& f,
             const Eigen::Matrix3Xd& u) {
  const geometry::QuadratureSurface qs = geometry::sample_gauss(mesh, x, mesh.nb() + 4);
  const Eigen::MatrixXd fq = geometry::to_gauss(mesh, f, qs.interp);
  const Eigen::MatrixXd uq = geometry::to_gauss(mesh, u, qs.interp);
  double p = 0;
  for (int q = 0; q < qs.w.size(); ++q) p += qs.w[q] * fq.col(q).dot(uq.col(q));
  return p;
}

struct Balance {
  double energy_change = 0, work = 0;
  double mismatch() const { return std::abs(energy_change - work) / std::abs(energy_change); }
};

// RK4 steps of dt to t_end at Ca; the work INT_0^t INT f.u dS dt by the trapezoidal rule over the
// steps (f in Gs / a, u in G a: the power in Gs a G; E in Gs a^2, t in 1/G). The balance at
// t = 1, 2, ..., t_end (the last entry at t_end).
std::vector<Balance> run(int nb, double ca, double dt, double t_end) {
  const geometry::Mesh mesh(6, nb);
  const membrane::LawOptions law{membrane::LawKind::NeoHookean};
  Capsule cap(mesh, law, Flow::simple_shear());
  const membrane::Membrane m(mesh, mesh.reference(), membrane::make_law(law));
  const auto rate = [&](const Eigen::Matrix3Xd& x) {
    return power(mesh, x, cap.traction(x), cap.velocity(x, ca));
  };
  std::vector<Balance> out;
  Balance b;
  const double e0 = m.energy(cap.positions());
  double p_prev = rate(cap.positions());
  const int steps = static_cast<int>(std::lround(t_end / dt));
  for (int k = 1; k <= steps; ++k) {
    cap.step(dt, [ca](double) { return ca; });
    const double p = rate(cap.positions());
    b.work += 0.5 * dt * (p_prev + p);
    p_prev = p;
    const double t = k * dt;
    if (k == steps || std::abs(t - std::round(t)) < 0.5 * dt) {
      b.energy_change = m.energy(cap.positions()) - e0;
      out.push_back(b);
    }
  }
  return out;
}

// The balance through the overshoot (D peaks at t ~ 3.5) to the tank-treading state (t = 8) at
// NB: prints the mismatch at every time unit; returns the balances.
std::vector<Balance> tank_treading(int nb, double dt) {
  const std::vector<Balance> b = run(nb, 0.6, dt, 8.0);
  std::printf("NB=%d, dt=%g: W(t) - (E(t) - E(0)) at t = 1..8:", nb, dt);
  for (const Balance& s : b) std::printf(" %.2e", s.work - s.energy_change);
  std::printf("; relative at t = 8: %.2e\n", b.back().mismatch());
  return b;
}

}  // namespace

TEST(EnergyBalance, NeoHookeanShearAtCa06) {
  // Measured (dt = 0.004): relative mismatch 2.1e-3 (NB=6), 4.2e-5 (NB=8), 3.3e-5 (NB=10), the
  // last two at the level of the trapezoidal rule's O(dt^2).
  std::vector<double> mismatch;
  for (int nb : {6, 8, 10}) {
    const Balance b = run(nb, 0.6, 0.004, 1.0).back();
    mismatch.push_back(b.mismatch());
    std::printf("NB=%d: E(1) - E(0) = %.8f, INT_0^1 INT f.u dS dt = %.8f, relative mismatch %.2e\n",
                nb, b.energy_change, b.work, mismatch.back());
  }
  EXPECT_LT(mismatch[1], 0.1 * mismatch[0]);
  EXPECT_LT(mismatch[2], 1e-4);
}

// Through the overshoot the tips sharpen (at NB=10 the health monitor's resolution warning fires
// at t = 1.4) and the discrete balance is no longer kept to the step's rounding. Measured, relative
// mismatch at t = 8: 4.9e-2 (NB=8), 1.9e-2 (NB=10, the same with dt = 0.002), 8.3e-3 (NB=12),
// 3.6e-3 (NB=14, dt = 0.003): it falls like NB^-4.4..-5.4, it is gained while the tips are sharpest
// (t = 2..5) and hardly grows in the tank-treading state (t = 6..8). The test asserts the fall
// from NB=8 to 10 and that the tank-treading state adds under a tenth of the mismatch at NB=10.
TEST(EnergyBalance, NeoHookeanShearThroughTheOvershootConvergesInNb) {
  const std::vector<Balance> b8 = tank_treading(8, 0.004), b10 = tank_treading(10, 0.004);
  EXPECT_LT(b10.back().mismatch(), 0.5 * b8.back().mismatch());
  const auto gap = [](const Balance& s) { return s.work - s.energy_change; };
  EXPECT_LT(std::abs(gap(b10[7]) - gap(b10[5])), 0.1 * std::abs(gap(b10[7])));
}

// The finer rows of the measurement above (3-4 min):
//   build/tests/capsule/test_energy_balance --gtest_also_run_disabled_tests --gtest_filter='*14'
TEST(EnergyBalance, DISABLED_NeoHookeanShearThroughTheOvershootAtNb12And14) {
  const std::vector<Balance> b12 = tank_treading(12, 0.004), b14 = tank_treading(14, 0.003);
  EXPECT_LT(b14.back().mismatch(), b12.back().mismatch());
}
