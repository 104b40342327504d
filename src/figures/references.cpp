// capflow/figures/references: see references.h.
#include "figures/references.h"

namespace capflow::figures {

namespace {
const char* kPaper = "Dodson & Dimitrakopoulos (SBE)";
const char* kLac = "Lac et al. 2004 (BEM)";

double area_dilatation_modulus(const RunInfo& run) {
  if (run.law == "skalak") return 1 + 2 * run.c;
  if (run.law == "neo-hookean" || run.law == "mooney-rivlin") return 3;
  return 0;
}
}  // namespace

double small_deformation_slope(const RunInfo& run) {
  const double ks = area_dilatation_modulus(run);
  if (ks <= 0) return 0;
  const double planar = 1.25 * (3 + 1 / ks);
  if (run.flow == "planar-extension") return planar;
  if (run.flow == "simple-shear") return planar / 2;
  return 0;
}

std::vector<PublishedSteady> published_steady(const RunInfo& run) {
  if (run.flow != "planar-extension") return {};
  if (run.law == "skalak" && run.c == 1)
    return {{kPaper, true, 0.45, 0.548, 1.76},
            {kPaper, true, 0.6, 0.595, 1.90},
            {kLac, false, 0.45, 0.549, 1.78},
            {kLac, false, 0.6, 0.6, 1.95}};
  if (run.law == "neo-hookean")
    return {{kPaper, true, 0.18, 0.507, 1.60},
            {kPaper, true, 0.21, 0.552, 1.71},
            {kLac, false, 0.18, 0.504, 1.62},
            {kLac, false, 0.21, 0.552, 1.73}};
  return {};
}

}  // namespace capflow::figures
