// capflow/control/edit: applying a live edit of the control file to a running simulation.
//
// Policy (documented in the README): an edit is applied key by key. Keys that cannot change
// mid-run are refused with a message while the rest of the edit applies:
//   capsule.* (law, C, psi, viscosity_ratio), mesh.*, flow.*, numerics.symmetry,
//   numerics.smoothing, output.dir, output.png, output.mp4.*, render.*
// Everything else applies at the next step boundary: ca (the new schedule starts from the
// current Ca at the current time), steady.*, time.dt, time.t_end, output.csv_every,
// output.frame_every, output.checkpoint_every, output.vtk_every, numerics.volume_correction, numerics.threads,
// run.state, run.checkpoint_now.
// An edit that does not parse or validate is refused as a whole (the run keeps its settings).
#pragma once

#include <string>
#include <vector>

#include "control/options.h"

namespace capflow::control {

struct OptionChange {
  std::string path;       // e.g. "time.t_end", "ca"
  std::string old_value;  // JSON text
  std::string new_value;  // JSON text
  std::string reason;     // for refused changes: why
};

struct EditResult {
  ControlOptions merged;                // current options with the accepted changes applied
  std::vector<OptionChange> applied;
  std::vector<OptionChange> refused;
  bool schedule_changed = false;        // "ca" or "steady" changed: restart the schedule engine
};

EditResult apply_edit(const ControlOptions& current, const ControlOptions& edited);

}  // namespace capflow::control
