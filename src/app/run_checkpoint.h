// capflow/app/run_checkpoint: the one codec between a run's state and a checkpoint file
// (output/checkpoint.h), shared by --resume, start.from and the study programs of
// benchmarks/capsule.
//
// Records (names in the file): x (3 x num_local node positions), t, steps, elements, nb,
// division (0 cube, 1 box, 2 diagonal; absent = cube), law, ca (Ca at t; absent in checkpoints
// of earlier versions: recomputed from the schedule state), schedule (CaScheduler::state),
// health_normals, health_flags, frames, vtk_index, rows, steady_rows, resumes, wall_s,
// checkpoint_now_seen, control (the effective control file), control_file (the watched control
// file as last read; absent = control), pending_outputs (bits 1 row, 2 frame, 4 surface: the
// outputs of this step an output failure left unwritten; absent = 0) with pending_ca (the Ca
// they carry), pending_steady_ca (the Ca of an unwritten steady.csv row; NaN = none),
// h_next (the adaptive integrator's next step, time.dt "auto"; absent or 0 = estimate anew),
// step_history (its controller's memory, capsule::Integrator::History: e_prev, steps,
// h_free, and rho for time.method "chebyshev"; absent in checkpoints of earlier versions: the integrator restarts there),
// and note (free text: where a state that no run wrote came from, e.g. an extrapolation; absent =
// "").
#pragma once

#include <Eigen/Dense>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capsule/integrator.h"
#include "control/options.h"
#include "geometry/mesh.h"

namespace capflow::app {

struct RunCheckpoint {
  std::string path;                 // the file read or written
  std::string control;              // effective control file (JSON text)
  std::string control_file;         // the watched file's content as last read (JSON text)
  control::ControlOptions options;  // `control`, parsed (read_run_checkpoint)
  control::ControlOptions file_options;  // `control_file`, parsed (the base of live edits)
  std::shared_ptr<const geometry::Mesh> mesh;  // the mesh of `x` (read_run_checkpoint)
  Eigen::Matrix3Xd x;
  double t = 0;
  long steps = 0;
  double ca = 0;
  std::vector<double> schedule;
  Eigen::Matrix3Xd health_normals;
  std::vector<double> health_flags;
  long frames = 0, vtk_index = 0, rows = 0, steady_rows = 0, resumes = 0;
  double wall_s = 0;
  bool checkpoint_now_seen = false;
  bool pending_row = false, pending_frame = false, pending_vtk = false;
  double pending_ca = 0;
  double h_next = 0;
  std::optional<capsule::Integrator::History> step_history;
  Eigen::VectorXd krylov_warm;  // the viscosity-ratio solve's warm start (empty for lambda = 1)
  std::string note;
  double pending_steady_ca = std::numeric_limits<double>::quiet_NaN();
};

// Writes atomically (output::Checkpoint::write). OutputError naming the file on failure.
void write_run_checkpoint(const RunCheckpoint& state, const std::string& path);

// Reads and checks one checkpoint: UserError naming the file when it is foreign, corrupt,
// truncated, or inconsistent (a mesh that does not match its control, arrays of the wrong size,
// a non-finite state).
RunCheckpoint read_run_checkpoint(const std::string& path);

// "" when a checkpoint that read can be used, else why not (e.g. its rows are not all in the
// run's CSV files).
using CheckpointFits = std::function<std::string(const RunCheckpoint&)>;

// The newest checkpoint of a run directory that reads (and fits, when `fits` is given), or of a
// .ckpt file: that one. Newer ones that do not read or fit are listed in *skipped with why.
// UserError when none does.
RunCheckpoint read_latest_checkpoint(const std::filesystem::path& run_dir_or_file,
                                     std::vector<std::string>* skipped = nullptr,
                                     const CheckpointFits& fits = nullptr);

}  // namespace capflow::app
