// capflow/app/output_cadence: when the periodic outputs of a run are due.
//
// Each output (timeseries row, frame, ParaView surface, checkpoint) fires at the first step that
// reaches the next multiple of its cadence (output.*_every; 0 = never), with a guard of 1e-9 dt
// against round-off. A live edit of a cadence re-anchors that output at the current time.
#pragma once

#include "control/options.h"

namespace capflow::app {

struct Due {
  bool row = false, frame = false, vtk = false, checkpoint = false;
  // Shape diagnostics in full (extrema, edge curvature, tensions) are needed.
  bool full_measure() const { return row || frame || vtk; }
};

class OutputCadence {
 public:
  OutputCadence(const control::OutputOptions& o, double t) { reset_all(o, t); }
  // After a live edit: outputs whose cadence changed restart from t.
  void edit(const control::OutputOptions& before, const control::OutputOptions& after, double t);
  Due due(double t, double dt) const;
  // The earliest time an output is due (+inf when none is): adaptive steps end there.
  double next_time() const;
  // Moves the outputs that fired at t to their next time.
  void fired(const Due& d, const control::OutputOptions& o, double t);

 private:
  void reset_all(const control::OutputOptions& o, double t);
  double next_row_, next_frame_, next_vtk_, next_checkpoint_;
};

}  // namespace capflow::app
