// capflow figure: publication figures from run directories (headless).
//
// The 2-D figures (time series, profiles, steady-state curves) are made by src/figures: a
// gnuplot script <name>.gp plus its data <name>.dat each, kept beside the images so users can
// restyle and re-run `gnuplot <name>.gp` (figures/kinds.h lists them). This file holds the
// command line, the runs' descriptions from their control files, and the 3-D views: rendered
// off-screen (render::Renderer) from the run's saved state (app/saved_state.h), or, for a run
// without one, copied from the frame PNG nearest in time, and the output says so. figures.md in
// the output directory lists every figure with its caption, its sources and such notes.
//
// Kinds (--kinds, default all): timeseries, profiles, steady (figures/kinds.h), and
//   views       view_<run>_t<T>.png at --times (default: the final state), shaded and
//               coloured by tension with a colour bar (figs. 6c, 7c, 10)
//
// Example:
//   capflow figure runs/ca045 runs/ca125 -o docs/figures --times 0,0.5,1,18
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "app/commands.h"
#include "app/console.h"
#include "app/figure_args.h"
#include "app/run_directory.h"
#include "app/saved_state.h"
#include "app/surface_files.h"
#include "control/control_file.h"
#include "figures/format.h"
#include "figures/kinds.h"
#include "figures/run_tables.h"
#include "figures/writer.h"
#include "files/atomic_write.h"
#include "files/input_file.h"
#include "membrane/law.h"
#include "output/png_writer.h"
#include "render/renderer.h"

namespace capflow::app {
namespace {

namespace fs = std::filesystem;
using figures::RunInfo;
using figures::short_num;

// The largest sweep.csv read (10000 cases of a few hundred bytes each).
constexpr std::size_t kMaxSweepCsv = std::size_t{64} << 20;

// -o DIR: created when missing; a path that is not a directory, or cannot be made one, is a user
// error naming it.
void make_output_directory(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw UserError("-o " + dir + ": exists and is not a directory: give a directory for the figures");
  fs::create_directories(dir, ec);
  if (ec) throw UserError("-o " + dir + ": cannot create the directory: " + ec.message());
  if (::access(dir.c_str(), W_OK) != 0)
    throw UserError("-o " + dir + ": the directory is not writable: " + std::strerror(errno));
}

// A frame PNG copied to a figure (output failures name the figure).
void copy_frame(const std::string& from, const fs::path& to) {
  try {
    files::write_atomically(to.string(), files::read_input_file(from, "frame", 1u << 30));
  } catch (const files::InputError& e) {
    throw UserError(e.what());
  }
}

// ---- 3-D views

// Frame PNGs of a run with their times: the time of frame N is that of profile N (written at
// the same step); without profiles, N * output.frame_every from control.json.
std::vector<std::pair<double, std::string>> frames_with_times(const RunInfo& run,
                                                              std::string* how) {
  std::vector<std::pair<double, std::string>> out;
  const fs::path fd = fs::path(run.dir) / "frames";
  if (!fs::is_directory(fd)) return out;
  std::map<long, double> prof;
  for (const auto& r : figures::list_profiles(run.dir)) prof[r.index] = r.t;
  double every = 0;
  try {
    every = control::load_control_file((fs::path(run.dir) / "control.json").string())
                .options.output.frame_every;
  } catch (const std::exception&) {
  }
  *how = "";
  for (const auto& e : fs::directory_iterator(fd)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("frame_", 0) != 0 || e.path().extension() != ".png") continue;
    const long idx = std::atol(n.c_str() + 6);
    if (prof.count(idx)) {
      out.emplace_back(prof[idx], e.path().string());
      *how = "frame time from profiles/";
    } else if (every > 0) {
      out.emplace_back(idx * every, e.path().string());
      if (how->empty()) *how = "frame time = index * output.frame_every (control.json)";
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

void view_figures(figures::Writer& w, const FigureArgs& cmd, const std::vector<RunInfo>& runs) {
  using namespace capflow::render;
  const RenderOptions o = check_figure_args(cmd);
  std::optional<View> view;  // --view: instead of each run's camera
  if (!cmd.view_name.empty()) view = o.camera.view;
  // One renderer for every view: with the default colour range (render/color_range.h) the views
  // share one range that holds all of them, so one colour is one tension across the figures.
  std::unique_ptr<Renderer> renderer;
  std::string renderer_error;

  for (const auto& run : runs) {
    const auto surfaces = list_surfaces(run.dir);
    std::string how;
    const auto frames = frames_with_times(run, &how);
    // --times; by default the run's final state (its newest checkpoint, else its last surface)
    std::vector<std::optional<double>> want(cmd.times.begin(), cmd.times.end());
    if (want.empty()) want.push_back(std::nullopt);
    std::set<std::string> done;
    for (const std::optional<double>& t : want) {
      std::optional<SavedState> st;
      std::string note;
      try {
        st = load_saved_state(run.dir, t);
      } catch (const UserError& e) {
        note = e.what();
        if (!t && !surfaces.empty()) {  // no checkpoint that reads: the last surface
          try {
            st = load_saved_state(run.dir, surfaces.back().first);
          } catch (const UserError&) {
          }
        }
      }
      // named by the time drawn (the time asked for when nothing was drawn)
      const double t_name =
          st ? st->snapshot.time : (t ? *t : (frames.empty() ? 0.0 : frames.back().first));
      const std::string name =
          "view_" + figures::safe_name(run.label) + "_" + figures::time_tag(t_name);
      const bool elsewhere = t && std::abs(t_name - *t) > 1e-9 * (1 + std::abs(*t));
      if (elsewhere)
        w.note(name + ": requested t = " + short_num(*t) +
               ", nearest saved state t = " + short_num(t_name));
      if (!done.insert(name).second) continue;
      const fs::path png = w.out() / (name + ".png");
      bool rendered = false;
      if (st) {
        if (!renderer && renderer_error.empty()) {
          try {
            renderer = std::make_unique<Renderer>(o);
          } catch (const std::exception& e) {
            renderer_error = e.what();
            w.note("renderer unavailable (" + renderer_error + "): 3-D views fall back to frames");
          }
        }
        if (renderer) {
          CameraOptions cam = o.camera;
          if (st->camera && !view) cam = *st->camera;  // the run's camera
          renderer->set_camera(cam);
          Snapshot& s = st->snapshot;
          s.law = run.label + (run.law.empty() ? "" : ", " + run.law);
          Image img;
          renderer->render(s, &img);
          output::write_png(png.string(), img.width, img.height, img.rgba.data());
          std::ostringstream entry;
          entry << "- **" << name << "**: 3-D view of run " << run.label
                << " at t = " << short_num(s.time) << " (" << view_name(cam.view)
                << " view), coloured by " << field_label(o.field) << " (colour bar), rendered from "
                << st->note << " (paper figs. 6c, 7c, 10). Files: " << name << ".png.";
          w.record(name, entry.str());
          w.say("figure: " + name + " (" + name + ".png, rendered at t = " + short_num(s.time) +
                ")");
          rendered = true;
        }
      }
      if (rendered) continue;
      if (frames.empty()) {
        w.note(name + ": " + (note.empty() ? renderer_error : note) +
               " and no frames with known times; skipped");
        continue;
      }
      std::vector<double> ft;
      for (const auto& f : frames) ft.push_back(f.first);
      const auto& f = frames[static_cast<size_t>(figures::nearest(ft, t_name))];
      copy_frame(f.second, png);
      const std::string msg = name + ": NOT rendered at t = " + short_num(t_name) + " (" +
                              (note.empty() ? renderer_error : note) +
                              "): copied the nearest frame " + f.second +
                              " (t = " + short_num(f.first) + ", " + how + ")";
      w.note(msg);
      w.record(name, "- **" + name + "**: 3-D view of run " + run.label +
                         " from the saved frame nearest in time (see the note above). Files: " +
                         name + ".png.");
      w.say("figure: " + name + " (" + name + ".png, from frame t = " + short_num(f.first) + ")");
    }
  }
}

// A sweep directory (capflow sweep: sweep.csv and case_NNN/ run directories) given in place of a
// run stands for its cases, labelled by their values ("ca=0.3 capsule.C=1") from sweep.csv.
void expand_sweeps(FigureArgs* c) {
  if (!c->labels.empty()) return;
  std::vector<std::string> runs, labels;
  bool any = false;
  for (const std::string& r : c->runs) {
    const fs::path csv = fs::path(r) / "sweep.csv";
    if (RunDirectory::is_run(r) || !fs::is_regular_file(csv)) {
      runs.push_back(r);
      labels.push_back("");
      continue;
    }
    any = true;
    std::istringstream in(files::read_input_file(csv.string(), "sweep summary", kMaxSweepCsv));
    std::string header, line;
    std::getline(in, header);
    std::vector<std::string> keys;
    {
      std::stringstream h(header);
      for (std::string k; std::getline(h, k, ',');) keys.push_back(k);
    }
    const auto status_at = std::find(keys.begin(), keys.end(), "status") - keys.begin();
    while (std::getline(in, line)) {
      std::vector<std::string> v;
      std::stringstream row(line);
      for (std::string f; std::getline(row, f, ',');) v.push_back(f);
      if (v.empty()) continue;
      char name[32];
      std::snprintf(name, sizeof name, "case_%03d", std::atoi(v[0].c_str()));
      const fs::path dir = fs::path(r) / name;
      if (!RunDirectory::is_run(dir)) continue;
      std::string label;
      for (long k = 1; k < status_at && k < static_cast<long>(v.size()); ++k)
        label += (label.empty() ? "" : " ") + keys[k] + "=" + v[k];
      runs.push_back(dir.string());
      labels.push_back(label.empty() ? name : label);
    }
  }
  if (!any) return;
  c->runs = runs;
  c->labels = labels;
  for (size_t i = 0; i < runs.size(); ++i)
    if (c->labels[i].empty())
      c->labels[i] = fs::path(runs[i]).lexically_normal().filename().string();
}

// What the figures need to know of a run (law, flow) from its control.json; left empty when the
// file is missing or does not read (the references then do not apply).
RunInfo describe_run(const std::string& dir) {
  RunInfo r;
  r.dir = dir;
  try {
    const control::ControlOptions o =
        control::load_control_file((fs::path(dir) / "control.json").string()).options;
    r.law = membrane::to_string(o.law.kind);
    r.c = o.law.c;
    r.flow = o.flow.name();
  } catch (const std::exception&) {
  }
  return r;
}

int run(FigureArgs c) {
  check_figure_args(c);
  expand_sweeps(&c);
  if (c.runs.empty()) throw UserError("give at least one run directory (or a sweep directory)");
  check_labels(c);
  std::vector<RunInfo> runs;
  std::set<std::string> used;
  for (size_t i = 0; i < c.runs.size(); ++i) {
    if (!fs::is_directory(c.runs[i])) throw UserError("not a run directory: " + c.runs[i]);
    RunInfo r = describe_run(c.runs[i]);
    r.label = !c.labels.empty() ? c.labels[i]
                                : fs::path(c.runs[i]).lexically_normal().filename().string();
    if (r.label.empty() || r.label == ".")
      r.label = fs::absolute(c.runs[i]).lexically_normal().parent_path().filename().string();
    if (!used.insert(r.label).second) r.label += "_" + std::to_string(i + 1);
    runs.push_back(r);
  }

  make_output_directory(c.out);
  const bool gnuplot = !c.no_gnuplot && figures::gnuplot_on_path();
  figures::Writer w(c.out, c.vector, !c.no_png, gnuplot,
                    [](const std::string& line) { console::err(line); });
  std::ostringstream header;
  header << "# capflow figures\n\nWritten by `capflow figure` from:";
  for (const auto& r : runs) header << " `" << r.dir << "` (" << r.label << ")";
  header << ".\nEach 2-D figure has its gnuplot script `<name>.gp` and data `<name>.dat`; "
            "edit the script and run `gnuplot <name>.gp` to restyle. The captions below are "
            "the figures' titles.\n\n";
  if (!c.no_gnuplot && !gnuplot)
    w.note(
        "gnuplot not found (apt-get install gnuplot-nox, or scripts/setup): wrote the .gp "
        "and .dat files only");
  auto want = [&](const char* k) {
    return std::find(c.kinds.begin(), c.kinds.end(), k) != c.kinds.end();
  };
  figures::KindOptions ko;
  ko.times = c.times;
  ko.references = !c.no_references;
  try {
    if (want("timeseries")) {
      figures::timeseries_figures(w, runs, ko);
      figures::tank_treading_figures(w, runs);
    }
    if (want("profiles")) figures::profile_figures(w, runs, ko);
    if (want("steady")) figures::steady_figures(w, runs, ko);
    if (want("views")) view_figures(w, c, runs);
    w.write_manifest(header.str());
  } catch (const UserError&) {
    throw;
  } catch (const OutputError&) {
    throw;
  } catch (const files::WriteError& e) {  // a figure that cannot be written
    throw OutputError(e.what());
  } catch (const std::runtime_error& e) {  // a file that cannot be read
    throw UserError(e.what());
  }
  console::err("figure: " + std::to_string(w.written().size()) + " figures in " + c.out +
               " (list: figures.md)");
  if (w.written().empty()) throw UserError("no figure could be made from the given runs");
  if (!c.no_gnuplot && !gnuplot)
    throw OutputError(
        "gnuplot not found (apt-get install gnuplot-nox, or scripts/setup): the images of the 2-D "
        "figures were not made (their .gp and .dat files are in " +
        c.out + "; --no-gnuplot makes only those)");
  if (w.failures())
    throw OutputError(std::to_string(w.failures()) +
                      " figure(s) could not be drawn by gnuplot (figures.md and the "
                      "<name>.gnuplot.log files in " +
                      c.out + " say why)");
  return exit_code::kOk;
}

void setup(CLI::App& root) {
  auto c = std::make_shared<FigureArgs>();
  CLI::App* sub = root.add_subcommand(
      "figure",
      "Figures from run directories: time series, profiles, steady-state curves (gnuplot\n"
      "scripts + data + SVG/PDF + PNG) and 3-D views (rendered from the saved surface\n"
      "nearest in time; from the nearest frame PNG when the run saved no surface).\n"
      "figures.md in the output directory lists what was made and from what.");
  add_figure_args(sub, c.get());
  sub->callback([c] { set_exit_code(run(*c)); });
}

}  // namespace

CAPFLOW_COMMAND(30, setup);

}  // namespace capflow::app
