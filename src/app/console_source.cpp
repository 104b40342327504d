#include "app/console_source.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "app/errors.h"
#include "app/frames.h"
#include "app/run_directory.h"
#include "app/saved_state.h"
#include "app/simulation.h"
#include "app/surface_files.h"
#include "control/control_file.h"
#include "control/run_events.h"
#include "files/input_file.h"
#include "geometry/surface.h"

namespace capflow::app {

namespace fs = std::filesystem;

// ---- the timeline ---------------------------------------------------------------------------

std::shared_ptr<const render::Snapshot> SavedSurfaces::at(double t) {
  const auto list = list_surfaces(dir_);
  if (list.empty()) return nullptr;
  const std::pair<double, std::string>* best = &list[0];
  for (const auto& e : list)
    if (std::abs(e.first - t) < std::abs(best->first - t)) best = &e;
  std::lock_guard<std::mutex> lock(mutex_);
  if (best->second == cached_path_ && cached_) return cached_;
  render::Snapshot s;
  if (!load_surface(dir_, best->first, &s)) return nullptr;
  cached_path_ = best->second;
  cached_ = std::make_shared<const render::Snapshot>(std::move(s));
  return cached_;
}

std::vector<double> SavedSurfaces::times() {
  std::vector<double> t;
  for (const auto& e : list_surfaces(dir_)) t.push_back(e.first);
  return t;
}

// ---- the run in this process ----------------------------------------------------------------

RunFeed::RunFeed(const std::string& run_dir, const std::string& control_path,
                 control::Command command, render::RenderOptions render, std::string law)
    : dir_(run_dir),
      law_(std::move(law)),
      control_path_(control_path),
      command_(command),
      render_(std::move(render)),
      surfaces_(run_dir) {
  state_.live = true;
}

void RunFeed::observe(const StateRecord& s) {
  const capsule::Capsule& cap = *s.cap;
  // The positions of the last two steps (only this thread touches them): the nodes' speed over
  // the step that ended at the state drawn. A pause or the end reports that state again.
  if (s.phase == RunPhase::Running && cap.time() != last_t_) {
    std::swap(prev_x_, last_x_);
    prev_t_ = last_t_;
    last_x_ = cap.positions();
    last_t_ = cap.time();
  }
  std::unique_lock<std::mutex> lock(mutex_);
  serve::LiveState& st = state_;
  st.t = cap.time();
  st.ca = s.ca;
  st.dt = s.dt;
  st.steps = cap.step_count();
  if (s.m.shape.L > 0) {  // measured at this state (a row, frame or surface was due)
    st.D = s.m.shape.D;
    st.L = s.m.shape.L;
    st.S = s.m.shape.S;
    st.W = s.m.shape.W;
  }
  st.state = phase_name(s.phase);
  st.live = s.phase == RunPhase::Running || s.phase == RunPhase::Paused;
  // The pace over at least 2 s of wall time.
  if (pace_wall_ < 0 || s.phase != RunPhase::Running) {
    pace_wall_ = s.wall;
    pace_t_ = st.t;
    pace_steps_ = st.steps;
  } else if (s.wall - pace_wall_ >= 2) {
    const double w = s.wall - pace_wall_;
    st.steps_per_second = (st.steps - pace_steps_) / w;
    const double rate = (st.t - pace_t_) / w;
    st.eta_seconds = rate > 0 ? std::max(0.0, s.t_end - st.t) / rate : -1;
    pace_wall_ = s.wall;
    pace_t_ = st.t;
    pace_steps_ = st.steps;
  }
  const bool keep = s.phase != RunPhase::Running || !started_;
  if (!keep && !wanted_) return;
  started_ = true;
  wanted_ = false;
  if (s.schedule) {
    st.schedule_now = s.schedule->describe(st.t);
    st.schedule_next = s.schedule->describe_next();
  }
  lock.unlock();
  // The tensions, curvature and speed outside the lock: the API's readers never wait for them.
  const Eigen::Matrix3Xd& x = cap.positions();
  const Measures m = s.m.shape.L > 0 ? s.m : measure_state(cap, true);
  auto snap = std::make_shared<render::Snapshot>(state_snapshot(
      cap, x, cap.time(), s.ca, law_,
      {m.shape.D, m.shape.L, m.shape.S, m.shape.W, m.tau_max, m.tau_min}));
  const Eigen::VectorXd h = geometry::compute_geometry(cap.mesh(), x).mean_curvature;
  snap->curvature.assign(h.data(), h.data() + h.size());
  if (prev_x_.cols() == x.cols() && last_t_ == cap.time() && last_t_ > prev_t_) {
    const Eigen::VectorXd v = (last_x_ - prev_x_).colwise().norm() / (last_t_ - prev_t_);
    snap->speed.assign(v.data(), v.data() + v.size());
  }
  lock.lock();
  newest_ = std::move(snap);
  ++captures_;
  lock.unlock();
  fresh_.notify_all();
}

serve::LiveState RunFeed::state() {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

std::shared_ptr<const render::Snapshot> RunFeed::newest() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (state_.state != "running") return newest_;
  // The next step's state: drawn states are made only when asked for.
  const long seen = captures_;
  wanted_ = true;
  fresh_.wait_for(lock, std::chrono::milliseconds(250), [&] { return captures_ != seen; });
  return newest_;
}

// ---- a run directory ------------------------------------------------------------------------

namespace {

std::string read_small(const std::string& path) {
  try {
    std::string s = files::read_input_file(path, "run note", 1 << 16);
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    return s;
  } catch (const files::InputError&) {
    return "";
  }
}

// Column `name`'s value in the CSV row `row` under `header` (NaN when absent).
double column(const std::string& header, const std::string& row, const std::string& name) {
  size_t col = 0, at = 0;
  bool found = false;
  while (at <= header.size()) {
    size_t c = header.find(',', at);
    if (c == std::string::npos) c = header.size();
    if (header.compare(at, c - at, name) == 0 && c - at == name.size()) {
      found = true;
      break;
    }
    ++col;
    at = c + 1;
  }
  if (!found) return NAN;
  const char* p = row.c_str();
  for (size_t i = 0; i < col; ++i) {
    p = std::strchr(p, ',');
    if (!p) return NAN;
    ++p;
  }
  char* end = nullptr;
  const double v = std::strtod(p, &end);
  return end == p ? NAN : v;
}

}  // namespace

RunDirectorySource::RunDirectorySource(const std::string& dir)
    : dir_(dir),
      surfaces_(dir),
      rows_(dir + "/timeseries.csv", "time series"),
      events_(dir + "/events.jsonl", "event log") {
  if (!RunDirectory::is_run(dir))
    throw UserError(dir + " is not a capflow run directory (no control.json with events.jsonl "
                          "or checkpoints/)");
  control_path_ = read_small(dir + "/control.source");
  try {
    files::InputFile log(dir + "/run.log", "run log", std::size_t(1) << 40);
    if (log.read_prefix(4096).find("] capflow steady:") != std::string::npos) {
      command_ = control::Command::Steady;
      rows_ = serve::AppendedLines(dir + "/steady.csv", "steady states");
    }
  } catch (const files::InputError&) {
  }
  try {
    render_ = control::parse_control(files::read_input_file(dir + "/control.json",
                                                            "control file", 1 << 20),
                                     dir + "/control.json")
                  .options.render;
  } catch (const std::exception&) {
    render_ = render::RenderOptions{};  // the defaults: the page still shows the run
  }
}

RunDirectorySource::RunDirectorySource(const std::string& dir, const std::string& control_path,
                                       control::Command command, render::RenderOptions render)
    : dir_(dir),
      control_path_(control_path),
      command_(command),
      render_(std::move(render)),
      surfaces_(dir),
      rows_(dir + "/" + series_file(), "time series"),
      events_(dir + "/events.jsonl", "event log") {}

bool RunDirectorySource::alive() const {
  const int fd = ::open((dir_ + "/run.lock").c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat st {};
  bool held = false;
  if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
    if (::flock(fd, LOCK_SH | LOCK_NB) != 0)
      held = true;
    else
      ::flock(fd, LOCK_UN);
  }
  ::close(fd);
  return held;
}

serve::LiveState RunDirectorySource::state() {
  std::lock_guard<std::mutex> lock(mutex_);
  serve::LiveState s;
  rows_.refresh();
  events_.refresh();
  const auto& rows = rows_.lines();
  if (rows.size() >= 2 && rows_.first_index() == 0) {
    const std::string& h = rows[0];
    const std::string& r = rows.back();
    s.t = column(h, r, "t");
    s.ca = column(h, r, "ca");
    s.D = column(h, r, "D");
    s.L = column(h, r, "L");
    s.S = column(h, r, "S");
    s.W = column(h, r, "W");
    s.dt = column(h, r, "dt");
    const double steps = column(h, r, "steps");
    s.steps = std::isfinite(steps) ? static_cast<long>(steps) : 0;
  }
  s.live = alive();
  s.state = s.live ? "running" : "stopped";
  for (const std::string& line : events_.lines()) {
    const control::EventLine e = control::read_event_line(line);
    if (e.event == "pause") s.state = "paused";
    else if (e.event == "continue" || e.event == "resume" || e.event == "start") s.state = "running";
    else if (e.event == "end")
      // capflow run says why it ended; capflow steady's end says only its exit code.
      s.state = e.reason == "t_end reached" || e.reason.rfind("steady state", 0) == 0 ||
                        (e.reason.empty() && e.exit_code == 0)
                    ? "finished"
                    : "stopped";
  }
  if (!s.live && (s.state == "running" || s.state == "paused")) s.state = "stopped";
  return s;
}

std::shared_ptr<const render::Snapshot> RunDirectorySource::newest() {
  // The newest checkpoint or surface, whichever is later; read again only when it changed.
  std::string key;
  const auto surfaces = list_surfaces(dir_);
  const std::string ckpt = Simulation::latest_checkpoint(dir_);
  std::error_code ec;
  if (!ckpt.empty())
    key = ckpt + "@" + std::to_string(fs::last_write_time(ckpt, ec).time_since_epoch().count());
  if (!surfaces.empty()) key += "|" + surfaces.back().second;
  std::lock_guard<std::mutex> lock(mutex_);
  if (key == newest_key_ && newest_) return newest_;
  try {
    SavedState from_ckpt = load_saved_state(dir_, std::nullopt);
    render::Snapshot best = std::move(from_ckpt.snapshot);
    if (!surfaces.empty() && surfaces.back().first > best.time) {
      render::Snapshot s;
      if (load_surface(dir_, surfaces.back().first, &s)) best = std::move(s);
    }
    newest_ = std::make_shared<const render::Snapshot>(std::move(best));
  } catch (const std::exception&) {
    if (!surfaces.empty()) {
      render::Snapshot s;
      if (load_surface(dir_, surfaces.back().first, &s))
        newest_ = std::make_shared<const render::Snapshot>(std::move(s));
    }
  }
  newest_key_ = key;
  return newest_;
}

}  // namespace capflow::app
