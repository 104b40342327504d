// scripts/validate energy_balance: the energy balance of a neo-Hookean capsule in simple shear at
// Ca = 0.6 from rest through the overshoot to the tank-treading state (t = 8) at NB = 8 to 14
// (tests/capsule/energy_balance.h): E(8) - E(0) against the fluids' work, their relative mismatch
// and its observed order in NB. A markdown table on stdout; exit 1 when the mismatch does not fall
// with every refinement. About 4 minutes on 2 cores.
#include <cmath>
#include <cstdio>
#include <vector>

#include "energy_balance.h"

int main() {
  struct Row {
    int nb;
    double dt;
  };
  const std::vector<Row> rows{{8, 0.004}, {10, 0.004}, {12, 0.004}, {14, 0.003}};
  std::printf("| NB | dt | W(t) - (E(t) - E(0)) at t = 2 / 4 / 6 / 8 | E(8) - E(0) | relative at "
              "t = 8 | order in NB |\n");
  std::printf("|---:|---:|---|---:|---:|---:|\n");
  double last = 0;
  int last_nb = 0;
  bool falls = true;
  for (const Row& r : rows) {
    const std::vector<capflow::test::Balance> all =
        capflow::test::run_balance(r.nb, 0.6, r.dt, 8.0);  // at t = 1, 2, ..., 8
    const capflow::test::Balance& b = all.back();
    const double m = b.mismatch();
    std::printf("| %d | %g | ", r.nb, r.dt);
    for (int t = 2; t <= 8; t += 2)
      std::printf("%s%.2e", t > 2 ? " / " : "", all[t - 1].work - all[t - 1].energy_change);
    std::printf(" | %.4f | %.1e |", b.energy_change, m);
    if (last_nb > 0) {
      std::printf(" %.1f |\n", -std::log(m / last) / std::log(double(r.nb) / last_nb));
      falls = falls && m < last;
    } else {
      std::printf(" |\n");
    }
    std::fflush(stdout);
    last = m;
    last_nb = r.nb;
  }
  return falls ? 0 : 1;
}
