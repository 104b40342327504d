// capflow/app/console_source: the live console's two sources (serve/source.h).
//
// RunFeed: the run in this process (capflow run --serve). It observes the states the loop
// reports (RunOutputs::add_observer): their numbers at every step, and a drawable state
// (positions, tensions - app/frames.h: state_snapshot -, mean curvature, and the nodes' speed
// |dx/dt| over the step that ended there) when a client asks for an image (newest() waits up to
// 0.25 s for the next step's state while the run goes on), and always at the start, a pause and
// the end. With nobody watching, a step costs it a few stores under an uncontended lock and a
// copy of the positions.
// RunDirectorySource: a run directory (capflow view): the state from its timeseries.csv and
// events.jsonl, live while another process holds its lock, the newest state to draw from its
// newest surface or checkpoint (app/saved_state.h), edits to the file in control.source.
// Both give the timeline from the saved surfaces (surface.pvd, app/surface_files.h).
#pragma once

#include <Eigen/Dense>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>

#include "app/run_outputs.h"
#include "serve/appended_lines.h"
#include "serve/source.h"

namespace capflow::app {

// The saved surfaces of a run directory (the timeline), shared by both sources.
class SavedSurfaces {
 public:
  explicit SavedSurfaces(std::string dir) : dir_(std::move(dir)) {}
  std::shared_ptr<const render::Snapshot> at(double t);
  std::vector<double> times();

 private:
  std::string dir_;
  std::mutex mutex_;
  std::string cached_path_;
  std::shared_ptr<const render::Snapshot> cached_;
};

class RunFeed : public serve::Source {
 public:
  // `law`: the membrane law's name (the frames' text block).
  RunFeed(const std::string& run_dir, const std::string& control_path, control::Command command,
          render::RenderOptions render, std::string law);
  // The observer to add to the run's outputs.
  void observe(const StateRecord& s);

  serve::LiveState state() override;
  std::shared_ptr<const render::Snapshot> newest() override;
  std::shared_ptr<const render::Snapshot> saved(double t) override { return surfaces_.at(t); }
  std::vector<double> saved_times() override { return surfaces_.times(); }
  std::string run_dir() const override { return dir_; }
  std::string control_path() const override { return control_path_; }
  control::Command command() const override { return command_; }
  render::RenderOptions render_options() const override { return render_; }

 private:
  using clock = std::chrono::steady_clock;
  std::string dir_, law_, control_path_;
  control::Command command_;
  render::RenderOptions render_;
  SavedSurfaces surfaces_;
  std::mutex mutex_;
  serve::LiveState state_;
  std::shared_ptr<const render::Snapshot> newest_;
  bool wanted_ = false;            // a client waits for a newer state to draw
  long captures_ = 0;              // states kept for drawing so far
  std::condition_variable fresh_;  // a state was kept
  double pace_wall_ = -1, pace_t_ = 0;  // the last pace sample: wall seconds and t
  Eigen::Matrix3Xd prev_x_, last_x_;    // the positions of the last two steps
  double prev_t_ = -1, last_t_ = -1;
  long pace_steps_ = 0;
  bool started_ = false;
};

class RunDirectorySource : public serve::Source {
 public:
  // UserError when `dir` is not a capflow run directory.
  explicit RunDirectorySource(const std::string& dir);
  // The run directory of a command in this process that is about to create it (capflow steady
  // --serve): its control file and render settings are known already.
  RunDirectorySource(const std::string& dir, const std::string& control_path,
                     control::Command command, render::RenderOptions render);

  serve::LiveState state() override;
  std::shared_ptr<const render::Snapshot> newest() override;
  std::shared_ptr<const render::Snapshot> saved(double t) override { return surfaces_.at(t); }
  std::vector<double> saved_times() override { return surfaces_.times(); }
  std::string run_dir() const override { return dir_; }
  std::string control_path() const override { return control_path_; }
  control::Command command() const override { return command_; }
  render::RenderOptions render_options() const override { return render_; }

 private:
  bool alive() const;
  std::string dir_, control_path_;
  control::Command command_ = control::Command::Run;
  render::RenderOptions render_;
  SavedSurfaces surfaces_;
  std::mutex mutex_;
  serve::AppendedLines rows_, events_;
  std::string newest_key_;
  std::shared_ptr<const render::Snapshot> newest_;
};

}  // namespace capflow::app
