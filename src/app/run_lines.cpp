// capflow/app/run_lines: see run_lines.h.
#include "app/run_lines.h"

#include <omp.h>

#include <iomanip>
#include <sstream>

#include "app/format.h"
#include "control/control_file.h"
#include "membrane/membrane.h"
#include "parallel/team.h"
#include "spectral/simd_width.h"

namespace capflow::app {

std::string run_banner(const control::ControlOptions& o, const capsule::Capsule& cap,
                       const std::string& dir) {
  std::ostringstream m;
  m << "capflow run: " << membrane::to_string(o.law.kind) << ", " << o.flow.name()
    << ", NE=" << o.mesh.elements
    << (o.mesh.division == geometry::Division::Cube
            ? ""
            : std::string(" (") + control::division_name(o.mesh.division) + " division)")
    << " NB=" << o.mesh.nb << ", dt="
    << (o.time.adaptive ? "auto (tolerance " + shortest(o.time.tolerance) + ")"
                        : shortest(o.time.dt))
    << ", t_end=" << o.time.t_end << ", " << omp_get_max_threads() << " threads"
    << (parallel::size() > 1 ? " x " + std::to_string(parallel::size()) + " MPI ranks" : "")
    << ", kernels " << spectral::simd_width_name() << ", symmetry targets "
    << cap.symmetry().targets().size() << "/" << cap.mesh().num_unique();
  if (o.numerics.quadrature_scale != 1.0)
    m << ", quadrature orders x" << o.numerics.quadrature_scale;
  m << " -> " << dir;
  return m.str();
}

std::string steady_banner(const control::ControlOptions& o, const std::vector<double>& levels,
                          const capsule::Capsule& cap, const std::string& dir) {
  std::ostringstream m;
  m << "capflow steady: " << membrane::to_string(o.law.kind) << ", " << o.flow.name()
    << ", NE=" << o.mesh.elements << " NB=" << o.mesh.nb << ", ";
  if (const auto& c = o.ca.continuation)
    m << "the branch from Ca = " << c->from << " towards " << c->to << " (steps up to " << c->step
      << ")";
  else
    m << levels.size() << " level" << (levels.size() == 1 ? "" : "s") << " of Ca from "
      << levels.front() << " to " << levels.back();
  m << ", symmetry targets " << cap.symmetry().targets().size() << " -> " << dir;
  return m.str();
}

std::string progress_line(const RunProgress& p) {
  std::ostringstream line;
  line << "t=" << fixed(p.t, 4) << " Ca=" << fixed(p.ca, 4) << " D=" << fixed(p.D, 4)
       << " dt=" << std::setprecision(3) << p.dt << " " << fixed(p.steps_per_s, 1)
       << " steps/s, ETA " << fixed(p.eta_s, 0) << " s to t_end";
  if (p.eta_steady >= 0) line << ", steady in ~" << fixed(p.eta_steady, 2) << " (sim. time)";
  return line.str();
}

}  // namespace capflow::app
