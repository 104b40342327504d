// capflow/serve/source: what the live console shows, from one of two sources (app/console_source.h):
// the run in this process (capflow run|steady --serve: its states as the loop reports them) or
// a run directory (capflow view: the files a run writes, live or finished). The API
// (serve/api.h) reads everything through this interface and the run directory's files.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "control/schema.h"
#include "render/options.h"
#include "render/snapshot.h"

namespace capflow::serve {

struct LiveState {
  double t = 0, ca = 0, D = 0, L = 0, S = 0, W = 0, dt = 0;
  long steps = 0;
  std::string state = "running";  // "running", "paused", "stopped", "finished"
  std::string schedule_now, schedule_next;  // what the Ca schedule does now and next
  double steps_per_second = 0;              // over the last seconds of the run (0: unknown)
  double eta_seconds = -1;                  // to t_end at that pace (-1: unknown)
  bool live = false;                        // the run is still going on
};

class Source {
 public:
  virtual ~Source() = default;
  virtual LiveState state() = 0;
  // The newest state to draw (null when there is none yet). Live sources keep a state for
  // frames only while a client watches (watched() within the last seconds).
  virtual std::shared_ptr<const render::Snapshot> newest() = 0;
  virtual void watched() {}
  // The saved surface nearest to t (the timeline; null when the run saved none), and the times
  // of all of them.
  virtual std::shared_ptr<const render::Snapshot> saved(double t) = 0;
  virtual std::vector<double> saved_times() = 0;
  virtual std::string run_dir() const = 0;
  // The control file an edit is written to ("" when the run takes no edits).
  virtual std::string control_path() const = 0;
  virtual control::Command command() const = 0;
  // The run directory's table of rows for the plots and the state: timeseries.csv (capflow
  // run), steady.csv (capflow steady: one row per steady state).
  std::string series_file() const {
    return command() == control::Command::Steady ? "steady.csv" : "timeseries.csv";
  }
  // The run's render settings (colour map, background, overlay): the frames the page shows look
  // like its movie frames.
  virtual render::RenderOptions render_options() const = 0;
};

}  // namespace capflow::serve
