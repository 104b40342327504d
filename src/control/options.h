// capflow/control/options: the typed, validated content of a control file.
//
// Each option is documented once, in the schema table (control/schema_fields.cpp): its type, valid
// range, default, unit, edit policy and meaning, from which docs/control.md is generated. The
// comments here only name each field's JSON key. These structs are plain data: only
// src/control/control_file.cpp fills them from JSON (nothing else parses JSON).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "capsule/flow.h"
#include "geometry/mesh.h"
#include "membrane/law.h"
#include "geometry/reference_shape.h"
#include "membrane/bending.h"
#include "render/context.h"
#include "render/options.h"

namespace capflow::control {

struct MeshOptions {
  int elements = 10;  // "mesh.elements"
  int nb = 12;        // "mesh.nb"
  // "mesh.division" (geometry/mesh.h); when absent, default_division(elements, flow type)
  geometry::Division division = geometry::Division::Cube;
};

// The division of a control file that does not name one. In planar extension the capsule's
// tips (+-x) decide the accuracy, and the cube puts each of them in the middle of a 90-degree
// cap element: NE=6 gets the turned cube (the tips on element edges) and NE=10 the paper's
// parallelepiped (53-degree caps); NE=14 keeps the cube (its three rows along y already cut the
// tip region). Simple shear keeps the cube. (Skalak Ca=0.45, NB=8, t=1: volume drift -1.8e-4 /
// -1.9e-4 on the NE=6 / NE=10 cubes against -3.8e-6 / -1.9e-6 on these; docs/validation.md.)
inline geometry::Division default_division(int elements, capsule::FlowType flow) {
  if (flow != capsule::FlowType::PlanarExtension) return geometry::Division::Cube;
  if (elements == 6) return geometry::Division::Diagonal;
  if (elements == 10) return geometry::Division::Box;
  return geometry::Division::Cube;
}

// The control-file name of a division ("cube", "box", "diagonal").
inline const char* division_name(geometry::Division d) {
  return d == geometry::Division::Box        ? "box"
         : d == geometry::Division::Diagonal ? "diagonal"
                                             : "cube";
}

struct StartOptions {
  std::string from;            // "start.from" ("" = the reference sphere at rest)
  bool restore_volume = true;  // "start.restore_volume"
};

// The adaptive integrator (time.dt "auto"): an explicit Runge-Kutta pair whose steps find the
// stability limit, or a stabilized Runge-Kutta-Chebyshev method for stiff membranes.
enum class TimeMethod { CashKarp, Chebyshev };

struct TimeOptions {
  bool adaptive = true;     // "time.dt": "auto"
  TimeMethod method = TimeMethod::CashKarp;  // "time.method"
  double dt = 1e-3;         // "time.dt": a number (used when !adaptive)
  double tolerance = 1e-6;  // "time.tolerance"
  double t_end = 20;        // "time.t_end"
};

// One segment of a Ca schedule (the "ca" key as a list):
//   {"ca": 0.45, "hold": "steady"}       hold Ca until steady state
//   {"ca": 1.0, "hold": 5.0}             hold Ca for 5 time units
//   {"ramp": {"to": 2.5, "rate": 0.1}}   change Ca linearly at |dCa/dt| = rate
//   {"steps": {"to": 2.5, "by": 0.25, "hold": "steady"}}  the paper's gradual increase: jump by
//        `by` towards `to`, hold each level (until steady, or for a time), ending at `to`
struct CaSegment {
  enum class Kind { Hold, Ramp, Steps };
  Kind kind = Kind::Hold;
  double ca = 0;             // Hold: the level
  double to = 0;             // Ramp/Steps: the final level
  double rate = 0;           // Ramp: |dCa/dt| > 0
  double by = 0;             // Steps: increment > 0
  bool until_steady = true;  // Hold/Steps: hold until steady state ...
  double hold_time = 0;      // ... or for this long (when until_steady is false)
};

// "ca": {"continuation": {"from": 0.15, "to": 3, "step": 0.05}}: capflow steady's branch of
// steady states from `from` towards `to` by pseudo-arclength continuation (app/steady_run.h):
// the steps adapt between step/64 and `step` (the largest change of Ca per state), a fold
// (dCa/ds changes sign) is located and reported, and `after_fold` more states are computed on the
// branch beyond it; states land exactly on the Ca values of `at` where the branch passes them.
// capflow run refuses it (a run holds levels, ramps and steps).
struct Continuation {
  double from = 0;         // the first level, (0, 100]
  double to = 0;           // the end of the range, (0, 100], != from
  double step = 0;         // the first and the largest change of Ca per state, (0, 10]
  int after_fold = 3;      // states beyond a fold, [0, 1000] (0: the branch ends at the fold)
  std::vector<double> at;  // Ca values in the range to land on exactly (e.g. to compare with
                           // marched states), at most 1000
};

struct CaSchedule {
  std::vector<CaSegment> segments;  // "ca": a number n is [{"ca": n, "hold": "steady"}] that
                                    // never ends (the run ends at t_end)
  bool constant = false;            // true when "ca" was a plain number
  std::optional<Continuation> continuation;  // "ca": {"continuation": ...} (segments empty)
};

struct SteadyOptions {
  double tolerance = 1e-4;        // "steady.tolerance"
  double window = 0.5;            // "steady.window"
  double min_hold = 1.0;          // "steady.min_hold"
  bool stop = false;              // "steady.stop"
  double solve_tolerance = 1e-7;  // "steady.solve_tolerance"
};

struct Mp4Options {
  bool enabled = true;  // "output.mp4": false, true or an object
  int fps = 30;         // "output.mp4.fps"
  int quality = 23;     // "output.mp4.quality"
};

struct OutputOptions {
  std::string dir = "runs/capflow";  // "output.dir"
  double csv_every = 0.01;           // "output.csv_every"
  double frame_every = 0.0;          // "output.frame_every"
  bool png = true;                   // "output.png"
  Mp4Options mp4;                    // "output.mp4"
  double checkpoint_every = 0.0;     // "output.checkpoint_every"
  double vtk_every = 0.0;            // "output.vtk_every"
  int vtk_points = 25;               // "output.vtk_points"
};

struct NumericsOptions {
  bool smoothing = true;           // "numerics.smoothing"
  bool volume_correction = false;  // "numerics.volume_correction"
  bool symmetry = true;            // "numerics.symmetry"
  int threads = 0;                 // "numerics.threads"
  double quadrature_scale = 1.0;   // "numerics.quadrature_scale"
};

enum class RunState { Running, Paused, Stopped };

struct RunOptions {
  RunState state = RunState::Running;  // "run.state"
  bool checkpoint_now = false;         // "run.checkpoint_now"
};

struct ControlOptions {
  std::string description;       // "description"
  membrane::LawOptions law;      // "capsule.law", "capsule.C", "capsule.psi"
  double viscosity_ratio = 1.0;  // "capsule.viscosity_ratio"
  geometry::ReferenceShape shape;     // "capsule.shape": the stress-free and initial shape
  membrane::BendingOptions bending;   // "capsule.bending.*"
  MeshOptions mesh;              // "mesh"
  StartOptions start;            // "start"
  capsule::Flow flow;            // "flow.type", "flow.gradient"
  TimeOptions time;              // "time"
  CaSchedule ca;                 // "ca"
  SteadyOptions steady;          // "steady"
  OutputOptions output;          // "output"
  NumericsOptions numerics;      // "numerics"
  render::RenderOptions render;  // "render.*" (the renderer's own typed options)
  RunOptions run;                // "run"
};

}  // namespace capflow::control
