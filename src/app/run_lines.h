// capflow/app/run_lines: the lines capflow run and capflow steady say about a run in run.log and
// on the console - the first line (what runs, on what grid, with what, where) and the progress.
#pragma once

#include <string>
#include <vector>

#include "capsule/capsule.h"
#include "control/options.h"

namespace capflow::app {

// "capflow run: skalak, planar-extension, NE=6 NB=8, dt=auto (tolerance 1e-05), t_end=2, 2
// threads, kernels avx512, symmetry targets 44/218 -> DIR".
std::string run_banner(const control::ControlOptions& o, const capsule::Capsule& cap,
                       const std::string& dir);

// "capflow steady: skalak, planar-extension, NE=6 NB=8, 5 levels of Ca from 0.3 to 0.5,
// symmetry targets 44 -> DIR" (or "the branch from Ca = 0.3 towards 2 (steps up to 0.1)").
std::string steady_banner(const control::ControlOptions& o, const std::vector<double>& levels,
                          const capsule::Capsule& cap, const std::string& dir);

// capflow run's progress line.
struct RunProgress {
  double t = 0, ca = 0, D = 0, dt = 0;
  double steps_per_s = 0;
  double eta_s = 0;          // wall seconds to t_end
  double eta_steady = -1;    // simulated time to the next steady state (< 0: not known)
};
std::string progress_line(const RunProgress& p);

}  // namespace capflow::app
