// capflow/control/options: the typed, validated content of a control file.
//
// Every field documents its JSON key, default, unit and valid range. These structs are plain
// data: only src/control/control_file.cpp fills them from JSON (nothing else parses JSON).
// Units: lengths in the capsule radius a, time in 1/G (G the shear or extension rate),
// tensions in Gs, Ca = mu G a / Gs.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "capsule/flow.h"
#include "geometry/mesh.h"
#include "membrane/law.h"
#include "render/context.h"
#include "render/options.h"

namespace capflow::control {

struct MeshOptions {
  int elements = 10;  // "mesh.elements": 6 | 10 | 14 (paper fig. 1)
  int nb = 12;        // "mesh.nb": Gauss-Lobatto nodes per element direction, 4..24
  // "mesh.division": "cube" (the faces of the cube split in equal angles) | "box" (the paper's
  // parallelepiped of unit-square faces: NE=10 on a 2:1:1 box, NE=14 on 1:3:1) | "diagonal"
  // (NE=6 only: the cube turned 45 degrees about z, the +-x and +-y tips on element edges;
  // geometry/mesh.h). Default: default_division(elements, flow type).
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

// "start": the initial shape (default: the unstressed reference sphere at t = 0).
struct StartOptions {
  std::string from;            // "start.from": a run directory (its newest checkpoint) or a
                               // .ckpt file; its shape is resampled spectrally onto this run's
                               // mesh (geometry::resample_surface), which may differ in NB and
                               // elements; the run goes on from the checkpoint's time t, with its
                               // Ca schedule starting at t. "" = the reference sphere.
  bool restore_volume = true;  // "start.restore_volume": scale the resampled shape about its
                               // centroid to the reference volume (removes the source run's
                               // volume drift and the resampling error), so that volume_drift
                               // stays relative to the unstressed sphere
};

struct TimeOptions {
  // "time.dt": "auto" (adaptive steps with local error control, capsule/adaptive_stepper.h) or
  // a number: the fixed RK4 step, [1e-6, 0.1]; stable for dt < O(Ca dx_min).
  bool adaptive = true;
  double dt = 1e-3;         // the fixed step (used when !adaptive)
  double tolerance = 1e-6;  // "time.tolerance": local error tolerance of the adaptive steps
  double t_end = 20;        // "time.t_end": simulated end time, (0, 1e6]
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
  double tolerance = 1e-4;  // "steady.tolerance": max |dL/dt|, |dS/dt|, |dW/dt|, (0, 1]
  double window = 0.5;      // "steady.window": time over which the rates are measured, (0, 100]
  double min_hold = 1.0;    // "steady.min_hold": minimum time at a Ca level before a steady state
                            // may be declared, [0, 1e4]
  bool stop = false;        // "steady.stop": end the run at the steady state of the final level
                            // (after the last schedule segment; a constant "ca" has only that)
  double solve_tolerance = 1e-7;  // "steady.solve_tolerance": capflow steady's residual, max
                                  // |F| (node velocity, a G) at a root, [1e-12, 1e-3]
};

struct Mp4Options {
  bool enabled = true;  // "output.mp4": false or an object; true = defaults
  int fps = 30;         // "output.mp4.fps": 1..240
  int quality = 23;     // "output.mp4.quality": x264 CRF, 0 (lossless) .. 51 (worst)
};

struct OutputOptions {
  std::string dir = "runs/capflow";  // "output.dir": run directory (created)
  double csv_every = 0.01;           // "output.csv_every": timeseries.csv cadence (sim. time), > 0
  double frame_every = 0.0;          // "output.frame_every": movie/PNG frame cadence, 0 = none
  bool png = true;                   // "output.png": write frames/frame_NNNNNN.png
  Mp4Options mp4;                    // "output.mp4"
  double checkpoint_every = 0.0;     // "output.checkpoint_every": 0 = only at the end
  double vtk_every = 0.0;  // "output.vtk_every": ParaView surface_NNNNNN.vtp + surface.pvd
                           // cadence (simulated time), 0 = none
  int vtk_points = 25;     // "output.vtk_points": ParaView surface points per element edge (the
                        // interpolant at n Gauss-Lobatto points, app/surface_export.h); 0 = nodes
};

struct NumericsOptions {
  bool smoothing = true;           // "numerics.smoothing": paper's first-order smoothing
  bool volume_correction = false;  // "numerics.volume_correction": paper eq. 23
  bool symmetry = true;            // "numerics.symmetry": use the flow's symmetries
  int threads = 0;                 // "numerics.threads": OpenMP threads, 0 = all cores
  // "numerics.quadrature_scale": every quadrature order of the boundary integral (far, mid, own,
  // near) times this factor, for accuracy checks of a result against its quadrature (time per
  // velocity evaluation grows about as its square)
  double quadrature_scale = 1.0;
};

enum class RunState { Running, Paused, Stopped };

struct RunOptions {
  RunState state = RunState::Running;  // "run.state": "running" | "paused" | "stopped"
  bool checkpoint_now = false;         // "run.checkpoint_now": write a checkpoint once
};

// "render": how frames look (the renderer's own typed options; output paths are set by the run):
//   width, height (even, 16..7680), view ("oblique" | "xy" | "xz" | "yz"), orthographic (bool),
//   field ("max-tension" | "min-tension" | "mean-tension" | "plain"), colormap ("viridis" |
//   "coolwarm"), range ("auto" or [min, max]), element_lines (bool), overlay {"colorbar": bool,
//   "text": bool}, backend ("auto" | "egl" | "osmesa"), msaa (0..16), preview (bool: keep
//   preview.png in the run directory up to date without ever blocking the solver).

struct ControlOptions {
  std::string description;       // "description": free text, logged (optional)
  membrane::LawOptions law;      // "capsule.law", "capsule.C", "capsule.psi"
  double viscosity_ratio = 1.0;  // "capsule.viscosity_ratio": lambda, (0, 100]
  MeshOptions mesh;
  StartOptions start;  // "start"
  capsule::Flow flow;  // "flow.type": "planar-extension" | "simple-shear" |
                       // "custom" (with "flow.gradient": G, u = G x)
  TimeOptions time;
  CaSchedule ca;  // "ca": number or list of segments
  SteadyOptions steady;
  OutputOptions output;
  NumericsOptions numerics;
  render::RenderOptions render;  // "render"
  RunOptions run;
};

}  // namespace capflow::control
