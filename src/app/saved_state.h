// capflow/app/saved_state: a saved capsule state as the renderer's plain data, from what a run
// leaves behind, for `capflow render SOURCE`:
//   a .vtp surface file      the surface in it (tensions, t, Ca and the diagnostics stored);
//   a .ckpt checkpoint       its state: tensions from its membrane law, the shape diagnostics;
//   a run directory          with a time: the saved surface nearest to it (surface.pvd /
//                            vtk/*.vtp); without one, or when the run saved no surfaces, the
//                            newest checkpoint (the final state of a finished or stopped run).
// The camera is the run's (render.* of its control) when a checkpoint tells it.
// Failure: UserError naming the file or directory and why.
#pragma once

#include <optional>
#include <string>

#include "render/options.h"
#include "render/snapshot.h"

namespace capflow::app {

struct SavedState {
  render::Snapshot snapshot;
  std::optional<render::CameraOptions> camera;  // the run's, when known
  std::string note;                             // which file, at which time
};

SavedState load_saved_state(const std::string& source, std::optional<double> time);

}  // namespace capflow::app
