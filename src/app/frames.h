// capflow/app/frames: a run directory's movie and PNG frames through the renderer thread, shared
// by `capflow run` (a frame every output.frame_every) and `capflow steady` (a frame per state).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>

#include "app/run_directory.h"
#include "capsule/capsule.h"
#include "control/options.h"
#include "render/render_thread.h"
#include "render/snapshot.h"

namespace capflow::app {

// The renderer thread for the run directory: PNGs in frames/ (output.png), the movie
// `movie_name` (output.mp4), the live preview (render.preview); with the control file's render
// and output.mp4 settings. `frames`: false when the run writes no frames (only the preview).
// Null when neither frames nor a preview are wanted. The renderer sets itself up in its thread
// while the caller goes on; if that fails, submit_frame() returns false and error() says why.
std::unique_ptr<render::RenderThread> start_renderer(const control::ControlOptions& options,
                                                     RunDirectory& dir,
                                                     const std::string& movie_name, bool frames,
                                                     std::function<void(const std::string&)> say);

// "renderer: N movie frames written, solver waited M times for the renderer; ms per frame: ..."
std::string render_report(const render::RenderStats& stats);

// The plain data the renderer draws: positions x on cap's mesh, the principal tensions there,
// the time, Ca and the diagnostics shown in the overlay.
render::Snapshot state_snapshot(const capsule::Capsule& cap, const Eigen::Matrix3Xd& x, double time,
                                double ca, const std::string& law,
                                const render::SnapshotDiagnostics& diag);

}  // namespace capflow::app
