// capflow/app/run_outputs: the outputs of capflow run as observers of its states. The loop
// reports a state (StateRecord) with the outputs due there (OutputCadence); the sinks write:
//   frame    the renderer's movie frame and PNG (app/frames.h) and the frame's profiles
//            (profiles/profile_NNNNNN.csv: z = 0 and y = 0 cross-sections, plane,t,a,b)
//   surface  the ParaView surface (app/surface_export.h) and its surface.pvd entry
//   row      a timeseries.csv row (output/records.h: timeseries())
//   steady   a steady.csv row at a steady state (steady_run())
// in that order. What is due but not yet written stays pending: after an output failure the
// checkpoint records it (its Ca too) and a resume writes it first, so no row or frame is lost.
// Observers (the live console) see every state reported.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/output_cadence.h"
#include "app/run_checkpoint.h"
#include "app/run_lifecycle.h"
#include "capsule/capsule.h"
#include "control/schedule.h"
#include "control/options.h"
#include "diagnostics/diagnostics.h"
#include "output/vtk.h"
#include "render/snapshot.h"

namespace capflow::app {

// Shape diagnostics of a state and, in full, its principal tensions' extremes.
struct Measures {
  diagnostics::ShapeDiagnostics shape;
  double tau_max = 0, tau_min = 0;
  Eigen::Vector3d tau_min_at = Eigen::Vector3d::Zero();
  double bending_energy = 0;  // W_b (Gs a^2; 0 without bending), full measures only
};
Measures measure_state(const capsule::Capsule& cap, bool full);

// What the run is doing at a reported state (the live console's run state).
enum class RunPhase { Running, Paused, Stopped, Finished };
const char* phase_name(RunPhase p);  // "running", "paused", "stopped", "finished"

// A state as the outputs see it.
struct StateRecord {
  capsule::Capsule* cap = nullptr;  // at the state: its positions, time and step count
  double ca = 0;    // Ca in force during the step that ended here (a level change applies next)
  Measures m;       // full when a row, frame or surface is due
  double dt = 0;    // the step that ended here (0 before the first)
  double wall = 0;  // wall seconds of the run
  const control::CaScheduler* schedule = nullptr;  // the Ca schedule (null: none to describe)
  RunPhase phase = RunPhase::Running;  // not Running: the state stays (a pause, the end)
  double t_end = 0;                    // the run's end time now
};

class RunOutputs {
 public:
  RunOutputs(RunLifecycle& life, const control::ControlOptions& options);
  ~RunOutputs();

  // Counters and pending outputs as a checkpoint stores them, and their restoration.
  void store(RunCheckpoint* c) const;
  void restore(const RunCheckpoint& c);

  // The outputs due at the state being reported (and a steady state's row, at steady_ca):
  // pending until written, so that a checkpoint taken after a failure records them.
  void begin(const Due& due, double ca, std::optional<double> steady_ca = std::nullopt);
  // Writes the pending steady row, then the pending frame, surface and row (s.ca is replaced by
  // the Ca they were marked with).
  void write_steady(const StateRecord& s);
  void write_due(const StateRecord& s);
  // Anything pending (a resume after an output failure: what that step did not write, first).
  bool pending() const;
  // The preview image (render.preview), never blocking.
  void offer_preview(const StateRecord& s);

  long rows() const { return rows_; }
  long steady_rows() const { return steady_rows_; }
  // Frames a checkpoint counts: those whose files are written (call after the renderer's queue
  // drained), so that a resume never leaves a gap in the frame numbers.
  long frames_on_disk() const;
  // Frames handed to the renderer that it did not write (it failed with them queued).
  long frames_lost_in_flight() const;
  // Live edits of output.* (frozen keys aside: the surface's point count is read at each one).
  void set_options(const control::ControlOptions& options) { opt_ = options; }

  // Called with every state reported (the live console's feed), and with the state a pause or
  // the end leaves in place (notify).
  using Observer = std::function<void(const StateRecord&)>;
  void add_observer(Observer o) { observers_.push_back(std::move(o)); }
  void notify(const StateRecord& s) const {
    for (const Observer& o : observers_) o(s);
  }

 private:
  render::Snapshot snapshot(const StateRecord& s) const;
  void write_frame(const StateRecord& s);
  void write_profiles(const StateRecord& s, long index);
  void write_surface(const StateRecord& s);
  void write_row(const StateRecord& s);
  output::VtkSurface surface(const StateRecord& s) const;

  RunLifecycle& life_;
  control::ControlOptions opt_;
  std::unique_ptr<output::PvdCollection> pvd_;
  long frames_ = 0, rows_ = 0, steady_rows_ = 0, vtk_index_ = 0;
  long session_first_frame_ = 0;  // the frame index this session started at
  Due pending_;
  double pending_ca_ = 0;
  double pending_steady_ca_;  // NaN: none
  std::vector<Observer> observers_;
};

}  // namespace capflow::app
