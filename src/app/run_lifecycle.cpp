// capflow/app/run_lifecycle: see run_lifecycle.h.
#include "app/run_lifecycle.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <tuple>

#include "app/console.h"
#include "app/errors.h"
#include "app/frames.h"
#include "capsule/capsule.h"
#include "control/control_file.h"
#include "figures/run_tables.h"
#include "files/input_file.h"
#include "geometry/surface.h"

namespace capflow::app {

namespace fs = std::filesystem;
using control::Record;

namespace {

std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> f;
  std::istringstream in(line);
  for (std::string x; std::getline(in, x, ',');) f.push_back(x);
  if (!line.empty() && line.back() == ',') f.emplace_back();
  return f;
}

// A run written by an earlier capflow, whose timeseries.csv lacks columns of the present layout
// `header` (dt, bending_energy): its header and every row are rewritten in the present layout by
// column name, the missing columns empty, so that the rows a resume appends line up with them (a
// torn last line stays torn). A header naming a column the present layout does not have is left
// alone: the checkpoint's row count decides what happens then.
void upgrade_timeseries(const RunDirectory& dir, std::string header) {
  const fs::path path = dir.file("timeseries.csv");
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  if (!header.empty() && header.back() == '\n') header.pop_back();
  const std::vector<std::string> now = csv_fields(header);
  std::string text;
  std::vector<std::string> before;
  try {
    files::InputFile in(path.string(), "time series", figures::kMaxTableBytes);
    const std::string head = in.read_prefix(4096);
    const size_t eol = head.find('\n');
    if (eol == std::string::npos || head.compare(0, eol, header) == 0) return;
    before = csv_fields(head.substr(0, eol));
    for (const std::string& name : before)
      if (std::find(now.begin(), now.end(), name) == now.end()) return;
    text = in.read_all();
  } catch (const files::InputError& e) {
    throw UserError(e.what());
  }
  std::vector<long> from(now.size(), -1);  // the old column of each present one
  for (size_t i = 0; i < now.size(); ++i)
    for (size_t j = 0; j < before.size(); ++j)
      if (now[i] == before[j]) from[i] = static_cast<long>(j);
  std::ostringstream out;
  out << header << "\n";
  size_t pos = text.find('\n') + 1;
  while (pos < text.size()) {
    const size_t eol = text.find('\n', pos);
    const std::string line = text.substr(pos, eol == std::string::npos ? eol : eol - pos);
    const std::vector<std::string> old = csv_fields(line);
    for (size_t i = 0; i < now.size(); ++i)
      out << (i ? "," : "")
          << (from[i] >= 0 && from[i] < static_cast<long>(old.size()) ? old[from[i]] : "");
    if (eol == std::string::npos) break;
    out << "\n";
    pos = eol + 1;
  }
  dir.write_text("timeseries.csv", out.str());
}

// The control file a resumed run watches again: control.source names it ("" when the run had
// none, or the file named is gone).
std::string watched_control(const RunDirectory& dir) {
  std::string text;
  try {
    text = files::read_input_file(dir.file("control.source").string(), "control.source",
                                  std::size_t{64} << 10);
  } catch (const files::InputError&) {
    return "";
  }
  const std::string line = text.substr(0, text.find('\n'));
  std::error_code ec;
  return !line.empty() && fs::exists(line, ec) ? line : "";
}

// A checkpoint a resume can continue from: its rows are all whole lines of the CSV files (a
// torn last line - a crash mid-write - is cut off, and an older checkpoint taken when a recorded
// row is torn).
CheckpointFits rows_on_disk(const RunDirectory& dir) {
  const AppendFile::Lines ts = AppendFile::count_lines(dir.file("timeseries.csv"));
  const AppendFile::Lines st = AppendFile::count_lines(dir.file("steady.csv"));
  return [ts, st](const RunCheckpoint& c) -> std::string {
    if (c.rows + 1 > ts.whole)
      return "it recorded " + std::to_string(c.rows) + " rows of timeseries.csv, which holds " +
             std::to_string(std::max(0L, ts.whole - 1)) + " whole rows" +
             (ts.torn ? " and a torn one" : "");
    if (c.steady_rows + 1 > st.whole)
      return "it recorded " + std::to_string(c.steady_rows) + " rows of steady.csv, which holds " +
             std::to_string(std::max(0L, st.whole - 1)) + " whole rows" +
             (st.torn ? " and a torn one" : "");
    return "";
  };
}

// A resume continues from its checkpoint: the frames and profiles written after it (index >=
// frames) are made again, so the ones on disk go (a session that ends earlier leaves none that
// belong to no state of the run).
void remove_outputs_after(const RunDirectory& dir, long frames) {
  std::error_code ec;
  for (const auto& [sub, prefix, ext] :
       {std::tuple<const char*, const char*, const char*>{"frames", "frame_", ".png"},
        {"profiles", "profile_", ".csv"}}) {
    for (const auto& e : fs::directory_iterator(dir.file(sub), ec)) {
      const std::string n = e.path().filename().string();
      if (n.rfind(prefix, 0) != 0 || e.path().extension() != ext) continue;
      char* end = nullptr;
      const long index = std::strtol(n.c_str() + std::strlen(prefix), &end, 10);
      if (end && std::string(end) == ext && index >= frames) fs::remove(e.path(), ec);
    }
  }
}

// The movie of this session: the first of movie.mp4, movie.part2.mp4, ... that does not exist
// (a session whose movie could not hold a frame left none).
std::string movie_name(const RunDirectory& dir) {
  std::error_code ec;
  if (!fs::exists(dir.file("movie.mp4"), ec)) return "movie.mp4";
  for (int k = 2;; ++k) {
    const std::string name = "movie.part" + std::to_string(k) + ".mp4";
    if (!fs::exists(dir.file(name), ec)) return name;
  }
}

// start.from inside the run's own directory: a new run would overwrite what it starts from.
bool inside(const fs::path& p, const fs::path& d) {
  const std::string a = fs::weakly_canonical(fs::absolute(p)).string() + "/";
  const std::string b = fs::weakly_canonical(fs::absolute(d)).string() + "/";
  return a.compare(0, b.size(), b) == 0;
}

}  // namespace

std::unique_ptr<RunLifecycle> RunLifecycle::create(const NewRun& run, const Spec& spec,
                                                   const std::atomic<bool>* signal) {
  std::unique_ptr<RunLifecycle> l(new RunLifecycle());
  l->spec_ = spec;
  l->control_source_ = run.control_source;
  const control::ControlOptions& o = run.options;
  const fs::path out = o.output.dir;
  // Everything that can be refused is checked before the run directory is touched.
  if (!o.start.from.empty()) {
    if (inside(o.start.from, out))
      throw UserError("start.from: " + o.start.from + " is in this run's own directory (output.dir " +
                      out.string() +
                      "), whose outputs a new run overwrites: give another run's directory, or "
                      "continue this run with --resume");
    try {
      l->source_ = read_latest_checkpoint(o.start.from);
    } catch (const UserError& e) {
      throw UserError(std::string("start.from: ") + e.what());
    }
    const std::vector<control::ControlIssue> ti =
        spec.marches ? control::time_issues(o.time, l->source_->t)
                     : std::vector<control::ControlIssue>{};
    if (!ti.empty())
      throw UserError(ti[0].path + ": " + ti[0].message +
                      " (the run starts at the time of start.from)");
  }
  if (spec.check) spec.check(l->source_);
  l->dir_ = RunDirectory::open(
      out, run.overwrite ? RunDirectory::Mode::Overwrite : RunDirectory::Mode::Create);
  l->fresh_ = true;
  try {
    l->log_ = std::make_unique<RunLog>(*l->dir_, isatty(STDERR_FILENO));
    l->dir_->open_records(true, spec.timeseries_header, spec.steady_header);
    l->write_control(o);
    l->dir_->write_text(
        "control.source",
        (run.control_source.empty() ? "" : fs::absolute(run.control_source).string()) + "\n");
    l->open_feed(signal, false);
  } catch (...) {
    l->abandon();
    throw;
  }
  return l;
}

std::unique_ptr<RunLifecycle> RunLifecycle::resume(const std::string& run_dir, const Spec& spec,
                                                   const std::atomic<bool>* signal) {
  std::unique_ptr<RunLifecycle> l(new RunLifecycle());
  l->spec_ = spec;
  l->dir_ = RunDirectory::open(run_dir, RunDirectory::Mode::Resume);
  RunDirectory& dir = *l->dir_;
  std::vector<std::string> skipped;
  upgrade_timeseries(dir, spec.timeseries_header);
  l->resumed_ = read_latest_checkpoint(run_dir, &skipped, rows_on_disk(dir));
  const RunCheckpoint& c = *l->resumed_;
  if (spec.check) spec.check(l->resumed_);
  // What a torn last line held is kept beside the file (e.g. timeseries.csv.torn).
  dir.timeseries().open(dir.file("timeseries.csv"), false);
  dir.timeseries().keep_lines(c.rows + 1, dir.file("timeseries.csv.torn"));
  dir.steady().open(dir.file("steady.csv"), false);
  dir.steady().keep_lines(c.steady_rows + 1, dir.file("steady.csv.torn"));
  dir.open_records(false, spec.timeseries_header, spec.steady_header);
  l->log_ = std::make_unique<RunLog>(dir, isatty(STDERR_FILENO));
  remove_outputs_after(dir, c.frames);
  l->wall_offset_ = c.wall_s;
  l->control_source_ = watched_control(dir);
  l->open_feed(signal, !l->control_source_.empty());
  for (const std::string& why : skipped)
    l->say("warning: skipped a checkpoint that does not read: " + why);
  l->event(Record()
               .set("event", "resume")
               .set("checkpoint", c.path)
               .set("steps", c.steps)
               .set("skipped", skipped),
           c.t);
  l->say("resuming " + run_dir + " from " + c.path + " at t = " + std::to_string(c.t));
  return l;
}

RunLifecycle::~RunLifecycle() {
  if (renderer_) renderer_->stop();
}

void RunLifecycle::open_feed(const std::atomic<bool>* signal, bool check_now) {
  feed_ = std::make_unique<ControlFeed>(control_source_, signal, check_now);
}

Eigen::Matrix3Xd RunLifecycle::start_shape(const geometry::Mesh& mesh, double volume,
                                           const control::ControlOptions& o) {
  const RunCheckpoint& src = *source_;
  Eigen::Matrix3Xd x = geometry::resample_surface(*src.mesh, src.x, mesh);
  if (!x.allFinite())
    throw UserError(src.path + ": the stored shape does not resample to a finite one");
  const double drift_before = capsule::enclosed_volume(mesh, x) / volume - 1.0;
  if (o.start.restore_volume) x = capsule::rescale_to_volume(mesh, x, volume);
  std::ostringstream m;
  m << "initial shape from " << src.path << " (NE=" << src.mesh->ne() << " NB=" << src.mesh->nb()
    << ", t = " << src.t << ", Ca = " << src.ca << ") resampled onto NE=" << mesh.ne()
    << " NB=" << mesh.nb() << "; its volume drift " << drift_before
    << (o.start.restore_volume ? " was removed (start.restore_volume)" : " is kept");
  say(m.str());
  event(Record()
            .set("event", "start_from")
            .set("checkpoint", src.path)
            .set("source_elements", src.mesh->ne())
            .set("source_nb", src.mesh->nb())
            .set("source_ca", src.ca)
            .set("volume_drift_before", drift_before)
            .set("restore_volume", o.start.restore_volume),
        src.t);
  return x;
}

void RunLifecycle::write_control(const control::ControlOptions& options) {
  dir_->write_text("control.json", control::to_json_text(options));
}

render::RenderThread* RunLifecycle::start_renderer(const control::ControlOptions& options,
                                                   bool frames) {
  renderer_ = app::start_renderer(options, *dir_, movie_name(*dir_), frames,
                                  [this](const std::string& line) { say(line); });
  return renderer_.get();
}

render::RenderStats RunLifecycle::stop_renderer() {
  if (!renderer_) return {};
  const render::RenderStats rs = renderer_->stop();
  const std::string err = renderer_->error();
  renderer_.reset();
  if (!err.empty()) throw OutputError("frames could not be written: " + err);
  return rs;
}

void RunLifecycle::drop_renderer() {
  if (!renderer_) return;
  renderer_->stop();
  renderer_.reset();
}

std::optional<RunLifecycle::Edit> RunLifecycle::next_edit(control::ControlOptions* opt,
                                                          control::ControlOptions* file_opt,
                                                          const control::EditPolicy& policy,
                                                          double t) {
  for (;;) {
    std::optional<ControlFeed::Saved> saved = feed_->take();
    if (!saved) return std::nullopt;
    if (!saved->parsed) {
      std::vector<std::string> errs;
      for (const auto& i : saved->issues) errs.push_back(i.str());
      say("refused edit of " + control_source_ + " (the run keeps its settings):\n  " +
          saved->error);
      event(Record().set("event", "edit").set("accepted", false).set("errors", errs), t);
      // A stop, a pause or a checkpoint request is honoured even when the rest is refused.
      if (saved->run_keys && (saved->run_keys->state != file_opt->run.state ||
                              saved->run_keys->checkpoint_now != file_opt->run.checkpoint_now)) {
        const control::RunState before = opt->run.state;
        opt->run = file_opt->run = *saved->run_keys;
        if (opt->run.state != before)
          say("run.state " + control::to_string(before) + " -> " +
              control::to_string(opt->run.state) + " applied (run keys are honoured alone)");
        write_control(*opt);
      }
      continue;
    }
    Edit e;
    e.result = control::apply_edit(*opt, *file_opt, saved->parsed->options, policy);
    e.warnings = saved->parsed->warnings;
    *file_opt = saved->parsed->options;
    if (e.result.empty()) continue;  // saved without changes to the run
    *opt = e.result.merged;
    write_control(*opt);
    return e;
  }
}

void RunLifecycle::report_edit(const Edit& e, double t, const std::string& note,
                               const control::Record& extra) {
  std::ostringstream m;
  m << "edit applied at t = " << t << ":";
  Record applied, refused;
  for (const auto& c : e.result.applied) {
    m << " " << c.path << " " << c.old_value << " -> " << c.new_value << ";";
    applied.set(c.path, control::change_record(c));
  }
  for (const auto& c : e.result.refused) {
    m << " refused " << c.path << " (" << c.reason << ");";
    refused.set(c.path, control::change_record(c));
  }
  if (!note.empty()) m << " " << note;
  say(m.str());
  for (const auto& w : e.warnings) say("warning: " + w.str());
  Record r = Record().set("event", "edit").set("accepted", true).set("applied", applied)
                 .set("refused", refused);
  r.merge(extra);
  event(r, t);
}

bool RunLifecycle::paused(const control::ControlOptions& options, double t) {
  if (options.run.state == control::RunState::Paused) {
    if (!paused_logged_) {
      say("paused at t = " + std::to_string(t) + " (set run.state to \"running\" to continue)");
      event(Record().set("event", "pause"), t);
      paused_logged_ = true;
    }
    return true;
  }
  if (paused_logged_) {
    say("running again");
    event(Record().set("event", "continue"), t);
    paused_logged_ = false;
  }
  return false;
}

void RunLifecycle::warn(const std::string& cause, const std::string& message, double t) {
  say("warning: " + message);
  event(Record().set("event", "warning").set("cause", cause).set("message", message), t);
}

void RunLifecycle::best_effort(const std::function<void()>& f) {
  try {
    f();
  } catch (const OutputError& e) {
    if (log_) log_->degrade();
    console::err(std::string("capflow: ") + e.what());
  }
}

fs::path RunLifecycle::store_checkpoint(const std::function<RunCheckpoint()>& make,
                                        long index) {
  if (renderer_) renderer_->wait_idle();
  const RunCheckpoint c = make();
  // The rows, frames and movie fragments it counts on stable storage before it is: a disk that
  // fails (a journal abort, a power cut) never leaves a checkpoint counting what was lost.
  dir_->sync();
  dir_->subdirectory("checkpoints");
  const fs::path path = dir_->checkpoint_path(index);
  write_run_checkpoint(c, path.string());
  return path;
}

bool RunLifecycle::keep_after_output_failure(const OutputError& e, double t,
                                             const std::function<void()>& last_checkpoint) {
  best_effort([&] { say(std::string("output failure: ") + e.what()); });
  best_effort([&] {
    event(Record().set("event", "failure").set("message", e.what()).set("cause", "output"), t);
  });
  const std::string dir = dir_->path().string();
  if (last_checkpoint) {
    try {
      last_checkpoint();
    } catch (const OutputError& e2) {
      best_effort([&] { say(std::string("final checkpoint not written: ") + e2.what()); });
    }
  }
  const std::vector<fs::path> kept = RunDirectory::checkpoints(dir);
  if (kept.empty() && fresh_) {
    console::err("capflow: the run could not start (" + std::string(e.what()) +
                 "); removed what it had written in " + dir);
    abandon();
    return false;
  }
  if (spec_.command == control::Command::Run)
    best_effort([&] {
      say(kept.empty() ? "no checkpoint to resume from"
                       : "resume with: capflow run --resume " + dir + " (from " +
                             kept.front().string() + ")");
    });
  drop_renderer();
  return true;
}

void RunLifecycle::end(const std::string& brief, control::Record end_event, double t) {
  best_effort([&] { say(brief); });
  best_effort([&] { event(std::move(end_event), t); });
}

double RunLifecycle::wall() const {
  return wall_offset_ +
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void RunLifecycle::abandon() {
  if (!fresh_ || !dir_) return;
  drop_renderer();
  feed_.reset();
  log_.reset();
  dir_->abandon();
  fresh_ = false;
}

}  // namespace capflow::app
