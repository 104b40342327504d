// capflow/app/run_lifecycle: what every command that runs a capsule shares, from its run
// directory's creation to its end event - capflow run, capflow steady, the runs of a sweep, and
// the live console that watches them. Each driver keeps only its own loop (app/simulation.h,
// app/steady_run.h); the outputs are observers of its states (app/run_outputs.h).
//
// A new run (create):
//   1. everything that can be refused is checked before the directory is touched (UserError,
//      exit 2, nothing created): start.from outside the run's own directory, readable, its time
//      before t_end; then the driver's own checks (Spec::check);
//   2. the directory is opened (RunDirectory: lock, Create or Overwrite), its records opened with
//      the layouts' headers (output/records.h), control.json and control.source written, the log
//      started;
//   3. a start that fails later, before its first checkpoint, removes what it wrote (abandon()).
// A resume (resume): the newest checkpoint whose rows are all whole in the CSVs (a torn tail cut
// off into <file>.torn), the files cut back to it, frames and profiles after it removed, the
// watched control file taken up again (with what was saved while the run was stopped).
// While it runs: start.from's shape (start_shape: resampled, and rescaled to the reference
// volume when start.restore_volume - in every command), the renderer's life, pauses (events
// "pause" and "continue"), the live control file (ControlFeed; edits applied under the command's
// policy, control/edit.h, and reported by report_edit), and at the end the summary line and the
// "end" event.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "app/control_feed.h"
#include "app/errors.h"
#include "app/run_checkpoint.h"
#include "app/run_directory.h"
#include "app/run_log.h"
#include "control/edit.h"
#include "control/options.h"
#include "control/record.h"
#include "geometry/mesh.h"
#include "render/render_thread.h"

namespace capflow::app {

// A new run.
struct NewRun {
  control::ControlOptions options;       // effective: command-line overrides applied
  control::ControlOptions file_options;  // as the control file says: the base of live edits
  std::string control_source;            // the control file to watch ("" = none)
  bool overwrite = false;                // replace an existing run in options.output.dir
};

class RunLifecycle {
 public:
  struct Spec {
    control::Command command = control::Command::Run;  // its edit policy and its name
    std::string timeseries_header, steady_header;      // the records' first lines
    bool marches = true;  // t_end matters (capflow run): a start.from past it is refused
    // The driver's checks once start.from's checkpoint (if any) is read, before the directory is
    // touched: UserError to refuse.
    std::function<void(const std::optional<RunCheckpoint>& source)> check;
  };

  static std::unique_ptr<RunLifecycle> create(const NewRun& run, const Spec& spec,
                                              const std::atomic<bool>* signal);
  // The run in `dir` continued from its newest usable checkpoint (UserError when there is none).
  static std::unique_ptr<RunLifecycle> resume(const std::string& dir, const Spec& spec,
                                              const std::atomic<bool>* signal);
  ~RunLifecycle();

  RunDirectory& dir() { return *dir_; }
  RunLog& log() { return *log_; }
  control::Command command() const { return spec_.command; }
  const std::string& control_source() const { return control_source_; }
  ControlFeed& feed() { return *feed_; }
  // start.from's checkpoint (a new run), or the checkpoint a resume continues.
  const std::optional<RunCheckpoint>& source() const { return source_; }
  const std::optional<RunCheckpoint>& resumed_from() const { return resumed_; }
  // A new run that has not begun its work yet: a failure now removes what it wrote (abandon).
  bool fresh() const { return fresh_; }
  // The run has begun (its first checkpoint, or its first level under way): a failure from now
  // on keeps what it wrote.
  void begun() { fresh_ = false; }

  // start.from's shape on `mesh`, rescaled to the reference `volume` when
  // options.start.restore_volume, and its line and "start_from" event. UserError when it does
  // not resample to a finite shape.
  Eigen::Matrix3Xd start_shape(const geometry::Mesh& mesh, double volume,
                               const control::ControlOptions& options);

  // The effective control file (control.json), after every applied edit.
  void write_control(const control::ControlOptions& options);

  // The renderer thread for `movie` frames (app/frames.h; null when neither frames nor a
  // preview are wanted), and its end: its report line; OutputError when frames were lost.
  render::RenderThread* start_renderer(const control::ControlOptions& options, bool frames);
  render::RenderThread* renderer() { return renderer_.get(); }
  render::RenderStats stop_renderer();
  void drop_renderer();  // after a failure: stopped, its error already reported

  // The next saved version of the control file, applied to *opt / *file_opt under the command's
  // policy (veto: app-specific refusals). A version refused as a whole is reported here (its
  // run keys still applied); nullopt when nothing is left to take.
  struct Edit {
    control::EditResult result;
    std::vector<control::ControlIssue> warnings;
  };
  std::optional<Edit> next_edit(control::ControlOptions* opt, control::ControlOptions* file_opt,
                                const control::EditPolicy& policy, double t);
  // The line and the "edit" event of an applied edit; `note`: what the driver did with it;
  // `extra`: fields the event adds (capflow run: the Ca after it).
  void report_edit(const Edit& e, double t, const std::string& note,
                   const control::Record& extra = {});

  // True while options.run.state is "paused"; the change is logged once each way ("pause",
  // "continue" events).
  bool paused(const control::ControlOptions& options, double t);

  void say(const std::string& line) { log_->say(line); }
  void event(control::Record e, double t) { log_->event(std::move(e), t); }
  void warn(const std::string& cause, const std::string& message, double t);

  // f(), with an output failure in it noted on stderr instead (the log degraded): what is said
  // after a failure, or at the end, must not end the run's report.
  void best_effort(const std::function<void()>& f);

  // A checkpoint at checkpoints/<index> (RunDirectory::checkpoint_path), made by `make` once
  // the renderer's queue has drained (so that it counts the frames on disk) and written after
  // what it counts is on stable storage (the file system synced). Its path.
  std::filesystem::path store_checkpoint(const std::function<RunCheckpoint()>& make, long index);

  // After an output failure `e` at time t: said, and the "failure" event (cause "output"); then
  // `last_checkpoint` (may be empty) keeps the state if the disk still takes a checkpoint (its
  // own OutputError is said). The renderer is dropped. False when the run has no checkpoint and
  // is new: its start failed, and what it wrote is removed (abandon).
  bool keep_after_output_failure(const OutputError& e, double t,
                                 const std::function<void()>& last_checkpoint);

  // The summary line and the "end" event (best effort: the run's outcome is decided).
  void end(const std::string& brief, control::Record end_event, double t);

  // Wall seconds of this run, earlier sessions of a resumed run included.
  double wall() const;
  // A new run that fails before its first checkpoint: what it wrote is removed.
  void abandon();

 private:
  RunLifecycle() = default;
  void open_feed(const std::atomic<bool>* signal, bool check_now);

  Spec spec_;
  std::unique_ptr<RunDirectory> dir_;
  std::unique_ptr<RunLog> log_;
  std::unique_ptr<ControlFeed> feed_;
  std::unique_ptr<render::RenderThread> renderer_;
  std::optional<RunCheckpoint> source_, resumed_;
  std::string control_source_;
  bool fresh_ = false;
  bool paused_logged_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double wall_offset_ = 0;
};

}  // namespace capflow::app
