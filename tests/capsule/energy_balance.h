// The energy balance of a capsule run (tests/capsule/test_energy_balance.cpp explains it): the
// strain energy's change against the fluids' work along a run, for the test and for the table
// of scripts/validate (table_energy_balance).
#pragma once

#include <cmath>
#include <vector>

#include "capsule/capsule.h"
#include "geometry/surface.h"
#include "membrane/membrane.h"

namespace capflow::test {

// INT f.u dS on the surface x (Gauss quadrature on the interpolated surface, NB + 4 points).
inline double power(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x,
                    const Eigen::Matrix3Xd& f, const Eigen::Matrix3Xd& u) {
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
inline std::vector<Balance> run_balance(int nb, double ca, double dt, double t_end) {
  const geometry::Mesh mesh(6, nb);
  const membrane::LawOptions law{membrane::LawKind::NeoHookean};
  capsule::Capsule cap(mesh, law, capsule::Flow::simple_shear());
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

}  // namespace capflow::test
