// capflow/app/run_summary: how a run of capflow run or capflow steady ended (Ceres' Solver::
// Summary): a termination enum, the figures of the "end" event, one line for the log
// (BriefReport) and the exit code (app/errors.h: 0, 4 a failed simulation, 5 an output failure).
#pragma once

#include <optional>
#include <string>

#include "control/record.h"

namespace capflow::app {

// Why capflow run ended (Ceres' TerminationType): its exit code follows from it.
enum class RunTermination {
  TEndReached,       // t_end reached
  SteadyStop,        // the steady state of the final level (steady.stop)
  Stopped,           // run.state "stopped"
  Signal,            // SIGINT, SIGTERM or SIGHUP
  SimulationFailed,  // exit 4: the health check or the integrator
  OutputFailed,      // exit 5: a run file could not be written
};
// In words: the "end" event's reason ("t_end reached", ...).
const char* reason_of(RunTermination t);

struct RunSummary {
  RunTermination termination = RunTermination::TEndReached;
  bool failed = false;         // the simulation failed (exit 4)
  bool output_failed = false;  // a run file could not be written (exit 5)
  std::string failure;         // message when failed or output_failed
  std::string reason;          // why the run ended, in words (the "end" event's reason)
  double t = 0;
  long steps = 0;
  long rejected = 0;           // adaptive step attempts refused in this session
  long evaluations = 0;        // velocity evaluations in this session
  long krylov_iterations = 0;  // GMRES iterations of the viscosity-ratio solves (lambda != 1)
  double wall_s = 0;
  double D = 0, L = 0, S = 0, W = 0;
  double volume_drift = 0;
  bool viscosity_ratio = false;  // lambda != 1: the report names the GMRES iterations
  int steady_states = 0;  // reached in this session
  long steady_rows = 0;   // steady.csv's rows: every session's
  int exit_code() const;
  // One line: why it ended, where, what it cost, the shape ("end (t_end reached): t=...").
  std::string BriefReport() const;
  // The "end" event.
  control::Record end_event() const;
};

// Why capflow steady ended.
enum class SteadyTermination {
  Levels,           // every level solved (or the continuation's range covered)
  ResolutionLimit,  // the branch ended at its resolution limit or a singular point (exit 0)
  Stopped,          // a signal or run.state "stopped" (the states found are kept, exit 0)
  Failed,           // a level without a steady state (exit 4)
  OutputFailed,     // a run file could not be written (exit 5)
};

struct SteadySummary {
  SteadyTermination termination = SteadyTermination::Levels;
  int states = 0;       // steady states found
  int levels = 0;       // levels asked for (0 for a continuation)
  bool continuation = false;
  bool failed = false;  // a level had no steady state (exit 4)
  // The branch ended at its resolution limit (exit 0): continued from a steady state, the time
  // steps to the next level failed the health check (the tips sharpen beyond what NB resolves).
  bool resolution_limit = false;
  std::optional<double> fold_ca;  // a continuation passed a fold there
  bool output_failed = false;
  std::string failure;
  double wall_s = 0;
  long evaluations = 0;
  int exit_code() const;
  // One line: "end: 3 steady states of 3, 2280 velocity evaluations, wall 4.1 s".
  std::string BriefReport() const;
  // The "end" event.
  control::Record end_event() const;
};

}  // namespace capflow::app
