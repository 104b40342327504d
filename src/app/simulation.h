// capflow/app/simulation: the simulation driver behind `capflow run`.
//
// Owns the run directory and all run I/O (the solver modules do none):
//   control.json       the effective control file (every key, defaults filled in)
//   timeseries.csv     t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,
//                      inclination_deg,volume_drift,steps,wall_s   (every output.csv_every)
//   steady.csv         ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min (per steady state)
//   events.jsonl       one JSON object per event (start, steady, level change, warning, end)
//   run.log            the log lines also printed to stderr
// Semantics: fixed-dt RK4 until t_end, a stop request (SIGINT/SIGTERM: the current step is
// finished first), "run.state": "stopped", or a failure (health monitor): then the last good
// state is kept and the run ends with a message naming the cause, time and location.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "control/options.h"

namespace capflow::app {

struct RunSummary {
  bool failed = false;
  std::string failure;  // message when failed
  double t = 0;
  long steps = 0;
  double wall_s = 0;
  double D = 0, L = 0, S = 0, W = 0;
  double volume_drift = 0;
  int steady_states = 0;
};

class Simulation {
 public:
  explicit Simulation(const control::ControlOptions& options);
  ~Simulation();
  // Runs to completion. `stop` may be set from a signal handler.
  RunSummary run(const std::atomic<bool>* stop = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace capflow::app
