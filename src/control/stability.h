// capflow/control/stability: the stability limit of fixed RK4 steps (time.dt a number), fitted
// to limits measured over Ca, NB, NE, division and law (docs/performance.md, "Fixed steps: the
// stability limit"; benchmarks/capsule/stability_limits.sh and fit_stability.py).
//
// The limit h* of a run is the smallest along its path. Measured at the sphere and at steady
// states, the growth of perturbations under the step map (RK4, then the end-of-step smoothing):
//   Skalak: the limit falls as the capsule stretches (area stiffening): the steady state's
//           (the smaller of it and the sphere's, which it is at every Ca measured),
//           h* = c_s(NE, division) dx_min^1.127 Ca / (1 + 1.57 Ca), within 5 % of every
//           measured limit (rms 2 %);
//   neo-Hookean: its membrane softens as it stretches (steady limits 2-4x the sphere's): the
//           sphere's, h* = c_0(NE, division) dx_min^1.076 Ca, within 2.1 % of every measured
//           limit (rms 0.8 %): at the sphere the limit is proportional to Ca.
// Other laws (Mooney-Rivlin): the smaller of the two. dx_min: the smallest node spacing of the
// reference mesh (control_file.h: min_node_spacing). Fixed-step runs from rest at 0.95 h* ran to
// their end, at 1.05 h* the health check stopped them (the table's last rows).
#pragma once

#include "control/options.h"

namespace capflow::control {

// The estimated stability limit of fixed RK4 steps at Ca (> 0) on this mesh, for this law.
double fixed_step_limit(const MeshOptions& mesh, membrane::LawKind law, double ca);

}  // namespace capflow::control
