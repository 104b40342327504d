// capflow/figures/kinds: the figure kinds of `capflow figure`, each made from the run
// directories' tables and written through a Writer. A run without the data a kind needs is left
// out of it with a note; a kind with no data at all is skipped with a note.
//
//   timeseries  ts_D (with the paper's steady D where it applies), ts_LSW, ts_edge_curvature
//               (straining flows), ts_tension (paper figs. 5, 8, 9, 11, 13, 14), ts_D_ca (D(t)
//               over Ca(t): what a steered run was driven with), ts_volume_drift,
//               ts_inclination (simple shear); ts_tank_treading (simple shear with ParaView
//               surfaces: the phase of a membrane point, figures/tank_treading.cpp)
//   profiles    profiles_<run>_z / _y at the given times with the undisturbed unit circle (figs.
//               6ab, 7ab, 12ab); profiles_compare_z / _y: every run at the last time (fig. 15)
//   steady      steady_D_vs_ca (small-deformation lines, published values),
//   steady_half_lengths_vs_ca
//               (published L), steady_ScWc_vs_Lc, steady_ScWc_ratio_vs_Lc, steady_area_vs_ca,
//               steady_area_vs_Lc, steady_edge_curvature_vs_Lc (log y), steady_tau_max_vs_ca,
//               steady_tau_max_vs_Lc, steady_tau_max_vs_strain (figs. 16-22)
#pragma once

#include <string>
#include <vector>

#include "figures/figure.h"
#include "figures/overlay.h"
#include "figures/writer.h"
#include "output/records.h"

namespace capflow::figures {

struct KindOptions {
  std::vector<double> times;  // profiles: the times wanted (nearest available); empty: 4 spread
  bool references = true;     // theory lines and published values where they apply
};

void timeseries_figures(Writer& w, const std::vector<RunInfo>& runs, const KindOptions& o);
void steady_figures(Writer& w, const std::vector<RunInfo>& runs, const KindOptions& o);
void profile_figures(Writer& w, const std::vector<RunInfo>& runs, const KindOptions& o);
void tank_treading_figures(Writer& w, const std::vector<RunInfo>& runs);

// The runs that have <file> with the columns `need`, with their tables; the others are named in
// a note.
std::vector<RunTable> load_run_tables(Writer& w, const std::vector<RunInfo>& runs,
                                      const output::records::Layout& layout,
                                      const std::vector<std::string>& need);

}  // namespace capflow::figures
