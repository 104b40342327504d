// The energy balance of a capsule run: the membrane is elastic, so its strain energy changes at
// the rate the fluids work on it,
//   dE/dt = INT f.u dS   (f = n.(sigma_out - sigma_in) = -div_s tau, the traction jump, which is
//                         the variation of E per area; u the surface velocity).
// The identity holds for any surface motion; discretely it checks the run's tractions (smoothed
// tangents) against the strain energy of the interpolated surface along the actual trajectory,
// through the time integration and the smoothing of every step. Neo-Hookean capsule in simple
// shear at Ca = 0.6, the case where capflow's steady D lies ~0.02 above published codes
// (docs/validation.md, 15.3 "Against published codes"): E(1) - E(0) against the time integral of INT f.u dS.
#include <gtest/gtest.h>

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
};

// RK4 steps of dt to t_end at Ca; the work INT_0^T INT f.u dS dt by the trapezoidal rule over the
// steps (f in Gs / a, u in G a: the power in Gs a G; E in Gs a^2, t in 1/G).
Balance run(int nb, double ca, double dt, double t_end) {
  const geometry::Mesh mesh(6, nb);
  const membrane::LawOptions law{membrane::LawKind::NeoHookean};
  Capsule cap(mesh, law, Flow::simple_shear());
  const membrane::Membrane m(mesh, mesh.reference(), membrane::make_law(law));
  const auto rate = [&](const Eigen::Matrix3Xd& x) {
    return power(mesh, x, cap.traction(x), cap.velocity(x, ca));
  };
  Balance b;
  const double e0 = m.energy(cap.positions());
  double p_prev = rate(cap.positions());
  const int steps = static_cast<int>(std::lround(t_end / dt));
  for (int k = 0; k < steps; ++k) {
    cap.step(dt, [ca](double) { return ca; });
    const double p = rate(cap.positions());
    b.work += 0.5 * dt * (p_prev + p);
    p_prev = p;
  }
  b.energy_change = m.energy(cap.positions()) - e0;
  return b;
}

}  // namespace

TEST(EnergyBalance, NeoHookeanShearAtCa06) {
  // Measured (dt = 0.004): relative mismatch 2.1e-3 (NB=6), 4.2e-5 (NB=8), 3.3e-5 (NB=10), the
  // last two at the level of the trapezoidal rule's O(dt^2).
  std::vector<double> mismatch;
  for (int nb : {6, 8, 10}) {
    const Balance b = run(nb, 0.6, 0.004, 1.0);
    mismatch.push_back(std::abs(b.energy_change - b.work) / std::abs(b.energy_change));
    std::printf("NB=%d: E(1) - E(0) = %.8f, INT_0^1 INT f.u dS dt = %.8f, relative mismatch %.2e\n",
                nb, b.energy_change, b.work, mismatch.back());
  }
  EXPECT_LT(mismatch[1], 0.1 * mismatch[0]);
  EXPECT_LT(mismatch[2], 1e-4);
}
