// capflow/figures/references: what a run's figures are compared with, by default.
//
// - Small-deformation theory (Barthes-Biesel & Rallison 1981): D = slope * Ca as Ca -> 0, with
//   slope (5/4)(3 + 1/Ks) in planar extension and half that in simple shear, Ks the membrane's
//   area-dilatation modulus over G_s (Skalak 1 + 2C; neo-Hookean and Mooney-Rivlin 3).
// - The published steady states in planar extension that the paper quotes (Dodson &
//   Dimitrakopoulos, its comparison with Lac et al. 2004): Skalak C = 1 at Ca = 0.45 and 0.6,
//   neo-Hookean at Ca = 0.18 and 0.21, D and L from each code. Steady shapes in a pure straining
//   flow do not depend on the viscosity ratio (docs/method: the membrane is at rest), so they
//   apply at any lambda.
#pragma once

#include <string>
#include <vector>

#include "figures/figure.h"

namespace capflow::figures {

// 0 when no small-deformation result applies (law unknown, another flow).
double small_deformation_slope(const RunInfo& run);

struct PublishedSteady {
  std::string source;  // "Dodson & Dimitrakopoulos (SBE)", "Lac et al. 2004 (BEM)"
  bool paper;          // the paper's own value (the others it quotes for comparison)
  double ca, D, L;
};
// The published steady states for the run's law and flow (empty when none apply).
std::vector<PublishedSteady> published_steady(const RunInfo& run);

}  // namespace capflow::figures
