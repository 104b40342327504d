// capflow/control/limits: the documented caps on control input (docs/control.md, "Limits").
//
// They are checked before a document is walked, so that no input - at start, in a live edit, or
// stored in a checkpoint - can exhaust memory, recurse without bound or run without end.
#pragma once

#include <cstddef>

namespace capflow::control {

// Largest control file read (bytes). A larger file (or /dev/zero behind a symlink) is refused
// after reading one byte more than this.
constexpr std::size_t kMaxControlBytes = 1 << 20;
// Deepest nesting of objects and arrays in a control document (the schema needs 4:
// ca[i].steps.hold, flow.gradient[i][j]).
constexpr int kMaxControlDepth = 16;
// Longest "description" (bytes).
constexpr std::size_t kMaxDescriptionBytes = 64 * 1024;
// Smallest time step, and the most steps a run may be asked for (t_end / dt).
constexpr double kMinTimeStep = 1e-6;
constexpr double kMaxSteps = 1e7;

}  // namespace capflow::control
