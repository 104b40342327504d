// capflow/app/run_summary: see run_summary.h.
#include "app/run_summary.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "app/errors.h"

namespace capflow::app {

using control::Record;

const char* reason_of(RunTermination t) {
  switch (t) {
    case RunTermination::TEndReached:
      return "t_end reached";
    case RunTermination::SteadyStop:
      return "steady state of the final level (steady.stop)";
    case RunTermination::Stopped:
      return "run.state is \"stopped\"";
    case RunTermination::Signal:
      return "stopped by signal";
    case RunTermination::SimulationFailed:
      return "failure";
    case RunTermination::OutputFailed:
      return "output failure";
  }
  return "";
}

int RunSummary::exit_code() const {
  return outcome_exit_code(failed, output_failed);
}

std::string RunSummary::BriefReport() const {
  std::ostringstream fin;
  fin << "end (" << reason << "): t=" << t << " steps=" << steps << " (rejected " << rejected
      << ") velocity evaluations=" << evaluations;
  if (viscosity_ratio)
    fin << " (GMRES iterations " << krylov_iterations << ", " << std::setprecision(3)
        << static_cast<double>(krylov_iterations) / std::max<long>(1, evaluations)
        << " per evaluation)";
  fin << " wall=" << std::fixed << std::setprecision(1) << wall_s << " s, D=" << std::setprecision(5)
      << D << " L=" << L << " S=" << S << " W=" << W << ", volume drift " << std::scientific
      << std::setprecision(2) << volume_drift << ", steady states " << steady_rows;
  return fin.str();
}

Record RunSummary::end_event() const {
  return Record()
      .set("event", "end")
      .set("reason", reason)
      .set("exit_code", exit_code())
      .set("steps", steps)
      .set("velocity_evaluations", evaluations)
      .set("rejected_steps", rejected)
      .set("D", D)
      .set("L", L)
      .set("S", S)
      .set("W", W)
      .set("volume_drift", volume_drift)
      .set("wall_s", wall_s);
}

int SteadySummary::exit_code() const {
  return outcome_exit_code(failed, output_failed);
}

std::string SteadySummary::BriefReport() const {
  std::ostringstream m;
  m << "end: " << states << " steady state" << (states == 1 ? "" : "s");
  if (continuation) {
    m << " on the branch";
    if (fold_ca) {
      std::ostringstream f;
      f << std::fixed << std::setprecision(6) << *fold_ca;
      m << ", fold at Ca = " << f.str();
    }
  } else {
    m << " of " << levels;
  }
  m << ", " << evaluations << " velocity evaluations, wall " << std::fixed << std::setprecision(1)
    << wall_s << " s" << (failed ? " (" + failure + ")" : "");
  return m.str();
}

Record SteadySummary::end_event() const {
  Record end = Record()
                   .set("event", "end")
                   .set("states", states)
                   .set("resolution_limit", resolution_limit)
                   .set("exit_code", exit_code())
                   .set("velocity_evaluations", evaluations)
                   .set("wall_s", wall_s);
  if (fold_ca) end.set("fold_ca", *fold_ca);
  return end;
}

}  // namespace capflow::app
