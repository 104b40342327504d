// capflow/app/time_stepper: the time steps of `capflow run`, fixed or adaptive.
//
//   time.dt a number: classical RK4 with that step (Capsule::step), as before "auto" existed:
//     the same results bit for bit; the run ends at the step that reaches t_end - dt/2.
//   time.dt "auto": with time.tolerance, time.method "cash-karp": capsule::AdaptiveStepper
//     (ARKODE ERKStep, Cash-Karp 5(4), Gustafsson's controller), "chebyshev":
//     capsule::ChebyshevStepper (stabilized Runge-Kutta-Chebyshev, for stiff membranes). Every step ends at the next breakpoint at the latest: t_end, the next
//     output time (CSV, frame, ParaView, checkpoint) and the next change of the Ca schedule (the
//     end of a ramp or of a timed hold), so outputs and schedule changes fall on exact times.
// A failed health check (capsule/health.h) rejects the step: the fixed stepper keeps the last
// good state and reports the failure; the adaptive one retries the step at a quarter of its
// size (and reports a failure only below the smallest step, time.dt's floor).
// restart() re-initialises the adaptive integrator from the capsule's state with the step it
// proposed (controller history dropped): after a level change or an edit of Ca (Ca may jump).
// Checkpoints store next_step() and history() instead, and a resume starts from them: a
// checkpoint never changes the run, and a resume from any of them (a signal's too) continues
// bit for bit.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capsule/integrator.h"
#include "capsule/capsule.h"
#include "capsule/health.h"
#include "control/options.h"

namespace capflow::app {

class TimeStepper {
 public:
  using History = capsule::Integrator::History;
  // h_next: the adaptive integrator's first step (a checkpoint's; 0 = ARKODE's estimate);
  // history: the controller's memory a checkpoint saved (none: a fresh start).
  TimeStepper(capsule::Capsule& cap, const control::TimeOptions& time, double h_next = 0,
              const std::optional<History>& history = std::nullopt);
  ~TimeStepper();

  // A live edit of time.*: switching between "auto" and a fixed dt, or a new tolerance, applies
  // from the next step.
  void configure(const control::TimeOptions& time);
  bool adaptive() const { return time_.adaptive; }

  // True when the run has reached t_end.
  bool done(double t_end) const;

  struct Outcome {
    double dt = 0;        // the step taken
    std::string failure;  // "" or why no step could be taken (the state is unchanged)
    int rejected = 0;     // adaptive: attempts refused by the error test or the health check
    std::vector<capsule::HealthReport> warnings;
  };
  // One step with Ca(t), ending at t_stop at the latest (adaptive steps; a fixed dt ignores it).
  Outcome advance(double t_stop, const capsule::CaFunction& ca, capsule::HealthMonitor& health);

  // The step the next advance() starts with (fixed: dt).
  double next_step() const;
  // The adaptive controller's memory (a fixed dt: the default).
  History history() const;
  // Adaptive: start again from the capsule's state with next_step() (or h when h > 0).
  void restart(double h = 0);

 private:
  Outcome advance_fixed(const capsule::CaFunction& ca, capsule::HealthMonitor& health);
  Outcome advance_adaptive(double t_stop, const capsule::CaFunction& ca,
                           capsule::HealthMonitor& health);

  capsule::Capsule& cap_;
  control::TimeOptions time_;
  std::unique_ptr<capsule::Integrator> stepper_;
  const capsule::CaFunction* ca_ = nullptr;  // Ca(t) of the step being taken
};

}  // namespace capflow::app
