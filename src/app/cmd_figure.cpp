// capflow figure: publication figures from run directories (headless).
//
// Every 2-D figure is a gnuplot script <name>.gp plus its data <name>.dat (one block per data
// set, gnuplot `index i`), kept beside the images so users can restyle and re-run
// `gnuplot <name>.gp`. The script writes <name>.svg (or .pdf, --vector) and <name>.png.
// 3-D views are rendered off-screen (render::Renderer) from the saved surface nearest in time
// (surface.pvd / vtk/*.vtp, see figure_data.h); a run without surface data falls back to the
// frame PNG nearest in time, and the output says so. figures.md in the output directory lists
// every figure, its sources and such notes.
//
// Kinds (--kinds, default all):
//   timeseries  ts_D, ts_LSW, ts_edge_curvature (straining flows), ts_tension (paper figs. 5, 8, 9,
//               11, 13, 14), ts_ca (Ca(t)), ts_volume_drift, ts_inclination (simple shear)
//   profiles    profiles_<run>_z / _y at --times, with the undisturbed unit circle
//               (figs. 6ab, 7ab, 12ab); profiles_compare_z / _y: every run at the last --times
//               value (default: its last profile), fig. 15
//   steady      steady_half_lengths_vs_ca, steady_ScWc_vs_Lc, steady_ScWc_ratio_vs_Lc,
//               steady_area_vs_ca, steady_area_vs_Lc, steady_edge_curvature_vs_Lc (log y),
//               steady_tau_max_vs_ca, steady_tau_max_vs_Lc, steady_tau_max_vs_strain,
//               steady_D_vs_ca (with the small-deformation line)
//               (figs. 16-22)
//   views       view_<run>_t<T>.png at --times (default: the last saved time), shaded and
//               coloured by tension with a colour bar (figs. 6c, 7c, 10)
//
// Example:
//   capflow figure runs/ca045 runs/ca125 -o docs/figures --times 0,0.5,1,18
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/figure_data.h"
#include "app/render_flags.h"
#include "app/run_directory.h"
#include "app/saved_state.h"
#include "control/control_file.h"
#include "membrane/law.h"
#include "output/png_writer.h"
#include "render/renderer.h"

namespace capflow::app {
namespace {

namespace fs = std::filesystem;
using figures::Table;

RenderFlags figure_view_flags() {
  RenderFlags f;
  f.width = 1200;
  f.height = 900;
  return f;
}

struct FigureCmd {
  std::vector<std::string> runs;
  std::string out = "figures";
  std::vector<std::string> kinds{"timeseries", "profiles", "steady", "views"};
  std::vector<double> times;
  std::vector<std::string> labels;
  std::string vector = "svg";
  bool no_png = false, no_gnuplot = false;
  RenderFlags view = figure_view_flags();  // the 3-D views
  std::string view_name;                   // --view: instead of each run's camera
};

struct Run {
  std::string dir, label, law;
  bool shear = false;  // a simple-shear run (tank-treading: no +x tip; an inclination)
  // small-deformation theory (Barthes-Biesel & Rallison 1981): D = slope * Ca for Ca -> 0, from
  // the membrane's area-dilatation modulus Ks (Skalak 1 + 2C, neo-Hookean and Mooney-Rivlin 3):
  // (5/4)(3 + 1/Ks) in planar extension, half that in simple shear; 0 for other flows
  double small_deformation_slope = 0;
};

// ---- data blocks and figure scripts

struct Block {
  std::string comment;               // what the block holds (run, source file, time)
  std::vector<std::string> columns;  // column names
  std::vector<std::vector<double>> rows;
};

struct Series {
  int block = 0;
  int xcol = 1, ycol = 2;  // 1-based (gnuplot `using`)
  std::string title;
  std::string style;  // gnuplot style after `with`, e.g. "lines lw 2 lc 1 dt 1"
};

struct Figure {
  std::string name, title, paper, xlabel, ylabel;
  std::string key = "top left";
  bool logy = false, equal_aspect = false;
  std::vector<Block> blocks;
  std::vector<Series> series;
  std::vector<std::string> sources;
  std::vector<std::string> notes;
};

// Shortest text that reads back as the same double.
// A time for a legend or a message: 6 significant digits (2.9999999999998912 -> 3).
std::string short_num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string num(double v) {
  char buf[40];
  for (int p : {10, 15, 17}) {
    std::snprintf(buf, sizeof buf, "%.*g", p, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string gq(const std::string& s) {  // gnuplot single-quoted string
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("''") : std::string(1, c);
  return o + "'";
}

std::string shq(const std::string& s) {  // shell single-quoted string
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}

std::string safe_name(const std::string& s) {
  std::string o;
  for (char c : s)
    o += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return o.empty() ? "run" : o;
}

std::string time_tag(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t%.4g", t);
  return buf;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::trunc);
  f << text;
  if (!f) throw UserError("cannot write " + p.string());
}

void write_dat(const fs::path& p, const Figure& fig) {
  std::ostringstream o;
  o << "# capflow figure " << fig.name << ": " << fig.title << "\n";
  o << "# one block per data set, separated by two blank lines (gnuplot: index i)\n";
  for (size_t b = 0; b < fig.blocks.size(); ++b) {
    const Block& bl = fig.blocks[b];
    o << "# block " << b << ": " << bl.comment << "\n# columns:";
    for (const auto& c : bl.columns) o << " " << c;
    o << "\n";
    for (const auto& r : bl.rows) {
      for (size_t k = 0; k < r.size(); ++k) o << (k ? " " : "") << num(r[k]);
      o << "\n";
    }
    o << "\n\n";
  }
  write_text(p, o.str());
}

std::string gp_script(const Figure& fig, const std::string& vector_format, bool png) {
  std::ostringstream o;
  o << "# " << fig.name << ".gp: written by `capflow figure`; edit and re-run `gnuplot " << fig.name
    << ".gp`\n";
  o << "# " << fig.title << (fig.paper.empty() ? "" : " (paper " + fig.paper + ")") << "\n";
  o << "# data: " << fig.name << ".dat (block i = index i)\n";
  for (const auto& s : fig.sources) o << "# source: " << s << "\n";
  o << "set encoding utf8\n";
  o << "set title " << gq(fig.title) << " noenhanced\n";
  o << "set xlabel " << gq(fig.xlabel) << "\n";
  o << "set ylabel " << gq(fig.ylabel) << "\n";
  o << "set key " << fig.key << " box opaque\n";
  o << "set grid\n";
  if (fig.logy) o << "set logscale y\n";
  if (fig.equal_aspect) o << "set size ratio -1\n";
  o << "dat = " << gq(fig.name + ".dat") << "\n";
  o << "# vector image\n";
  if (vector_format == "pdf")
    o << "set terminal pdfcairo size 6in,4.5in enhanced font 'Sans,11'\n";
  else
    o << "set terminal svg size 800,600 dynamic enhanced font 'Sans,14' background '#ffffff'\n";
  o << "set output " << gq(fig.name + "." + vector_format) << "\n";
  o << "plot \\\n";
  for (size_t i = 0; i < fig.series.size(); ++i) {
    const Series& s = fig.series[i];
    o << "  dat index " << s.block << " using " << s.xcol << ":" << s.ycol << " with " << s.style
      << " title " << gq(s.title) << " noenhanced" << (i + 1 < fig.series.size() ? ", \\\n" : "\n");
  }
  if (png) {
    o << "# raster image\n";
    o << "set terminal pngcairo size 1000,750 enhanced font 'Sans,12'\n";
    o << "set output " << gq(fig.name + ".png") << "\n";
    o << "replot\n";
  }
  o << "set output\n";
  return o.str();
}

struct Context {
  FigureCmd cmd;
  fs::path out;
  bool gnuplot = false;
  int failures = 0;
  std::ostringstream manifest;
  std::vector<std::string> written;

  void note(const std::string& m) {
    std::cerr << "figure: " << m << "\n";
    manifest << "- note: " << m << "\n";
  }
};

bool has_gnuplot() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

void emit(Context& cx, const Figure& fig) {
  bool any = false;
  for (const auto& s : fig.series)
    if (!fig.blocks[static_cast<size_t>(s.block)].rows.empty()) any = true;
  if (!any) {
    cx.note(fig.name + ": skipped, no data in any run");
    return;
  }
  // Series whose block is empty would make gnuplot fail: leave them out.
  Figure f = fig;
  f.series.erase(std::remove_if(f.series.begin(), f.series.end(),
                                [&](const Series& s) {
                                  return f.blocks[static_cast<size_t>(s.block)].rows.empty();
                                }),
                 f.series.end());
  write_dat(cx.out / (f.name + ".dat"), f);
  write_text(cx.out / (f.name + ".gp"), gp_script(f, cx.cmd.vector, !cx.cmd.no_png));
  std::string files = f.name + ".gp, " + f.name + ".dat";
  if (cx.gnuplot) {
    const fs::path log = cx.out / (f.name + ".gnuplot.log");
    const std::string c = "cd " + shq(cx.out.string()) + " && gnuplot " + shq(f.name + ".gp") +
                          " > " + shq(log.filename().string()) + " 2>&1";
    const int rc = std::system(c.c_str());
    const fs::path vec = cx.out / (f.name + "." + cx.cmd.vector);
    if (rc != 0 || !fs::exists(vec) || fs::file_size(vec) == 0) {
      std::ifstream lf(log);
      std::stringstream ls;
      ls << lf.rdbuf();
      cx.note(f.name + ": gnuplot failed (exit " + std::to_string(rc) + "): " + ls.str());
      ++cx.failures;
    } else {
      fs::remove(log);
      files += ", " + f.name + "." + cx.cmd.vector + (cx.cmd.no_png ? "" : ", " + f.name + ".png");
    }
  }
  std::cerr << "figure: " << f.name << " (" << files << ")\n";
  cx.manifest << "- **" << f.name << "**: " << f.title
              << (f.paper.empty() ? "" : " (paper " + f.paper + ")") << ". Files: " << files << ".";
  if (!f.sources.empty()) {
    cx.manifest << " Sources:";
    for (const auto& s : f.sources) cx.manifest << " " << s;
    cx.manifest << ".";
  }
  cx.manifest << "\n";
  for (const auto& n : f.notes) cx.manifest << "  - " << n << "\n";
  cx.written.push_back(f.name);
}

// ---- x-y overlays from a per-run table

struct Quantity {
  std::string name;   // .dat column name
  std::string label;  // legend suffix
  std::function<double(const Table&, long)> f;
};

Quantity column(const std::string& name, const std::string& label = "") {
  return {name, label.empty() ? name : label,
          [name](const Table& t, long r) { return t.num(r, t.col(name)); }};
}

const char* kDash[] = {"1", "2", "4", "5", "3"};

// One block per run (rows with every value finite), one series per (run, y quantity): colour
// per run, dash type per quantity.
Figure overlay(const std::string& name, const std::string& title, const std::string& paper,
               const std::string& xlabel, const std::string& ylabel,
               const std::vector<std::pair<Run, Table>>& data, const Quantity& x,
               const std::vector<Quantity>& ys, bool points) {
  Figure fig;
  fig.name = name;
  fig.title = title;
  fig.paper = paper;
  fig.xlabel = xlabel;
  fig.ylabel = ylabel;
  for (size_t r = 0; r < data.size(); ++r) {
    const auto& [run, tb] = data[r];
    Block b;
    b.comment = "run " + run.label + " (" + tb.source + ")";
    b.columns.push_back(x.name);
    for (const auto& y : ys) b.columns.push_back(y.name);
    for (long i = 0; i < tb.rows(); ++i) {
      std::vector<double> row{x.f(tb, i)};
      for (const auto& y : ys) row.push_back(y.f(tb, i));
      if (std::all_of(row.begin(), row.end(), [](double v) { return std::isfinite(v); }))
        b.rows.push_back(std::move(row));
    }
    if (b.rows.empty())
      fig.notes.push_back("run " + run.label + ": no usable rows in " + tb.source);
    fig.sources.push_back(tb.source);
    const int block = static_cast<int>(fig.blocks.size());
    fig.blocks.push_back(std::move(b));
    for (size_t k = 0; k < ys.size(); ++k) {
      Series s;
      s.block = block;
      s.xcol = 1;
      s.ycol = static_cast<int>(k) + 2;
      s.title = ys.size() == 1 ? run.label : run.label + ": " + ys[k].label;
      s.style = std::string(points ? "linespoints pt 7 ps 0.6" : "lines") + " lw 2 lc " +
                std::to_string(r % 8 + 1) + " dt " + kDash[k % 5];
      fig.series.push_back(s);
    }
  }
  return fig;
}

// Runs that have <file> (with the needed columns); the others are named in a note.
std::vector<std::pair<Run, Table>> tables(Context& cx, const std::vector<Run>& runs,
                                          const std::string& file,
                                          const std::vector<std::string>& need) {
  std::vector<std::pair<Run, Table>> out;
  for (const auto& r : runs) {
    const fs::path p = fs::path(r.dir) / file;
    if (!fs::exists(p)) {
      cx.note("run " + r.label + ": no " + file + ", left out of the " + file + " figures");
      continue;
    }
    try {
      Table t = figures::read_csv(p.string());
      for (const auto& c : need)
        if (t.col(c) < 0) throw std::runtime_error(p.string() + ": no column '" + c + "'");
      out.emplace_back(r, std::move(t));
    } catch (const std::exception& e) {
      cx.note("run " + r.label + ": " + e.what() + "; left out");
    }
  }
  return out;
}

// The (run, table) pairs whose run passes keep.
template <class Keep>
std::vector<std::pair<Run, Table>> only(const std::vector<std::pair<Run, Table>>& data, Keep keep) {
  std::vector<std::pair<Run, Table>> out;
  for (const auto& d : data)
    if (keep(d.first)) out.push_back(d);
  return out;
}

void timeseries_figures(Context& cx, const std::vector<Run>& runs) {
  const auto data = tables(cx, runs, "timeseries.csv",
                           {"t", "D", "L", "S", "W", "edge_curvature", "tau_max", "tau_min"});
  if (data.empty()) return;
  const Quantity t = column("t");
  emit(cx, overlay("ts_D", "Taylor deformation D(t)", "figs. 5a, 11a", "t", "D", data, t,
                   {column("D")}, false));
  emit(cx, overlay("ts_LSW", "Half-lengths L, S, W (inertia ellipsoid) vs t", "figs. 5, 11", "t",
                   "half-length", data, t, {column("L"), column("S"), column("W")}, false));
  // the +x tip's curvature means nothing for a tank-treading (shear) capsule
  const auto straining = only(data, [](const Run& r) { return !r.shear; });
  if (!straining.empty())
    emit(cx,
         overlay("ts_edge_curvature", "Edge curvature (z = 0 profile, +x tip) vs t", "figs. 8, 13",
                 "t", "edge curvature", straining, t, {column("edge_curvature")}, false));
  emit(cx, overlay("ts_tension", "Principal tensions tau_max and tau_min vs t", "figs. 9, 14", "t",
                   "tension / G_s", data, t,
                   {column("tau_max", "τ_max"), column("tau_min", "τ_min")}, false));
  // Ca(t): what a steered run was driven with, beside its D(t)
  emit(cx, overlay("ts_ca", "Capillary number Ca(t)", "steering", "t", "Ca", data, t,
                   {column("ca", "Ca")}, false));
  // the runs that have the column (older runs lack it: left out with a note)
  const auto with = [&](const std::string& c) {
    return only(tables(cx, runs, "timeseries.csv", {"t", c}), [](const Run&) { return true; });
  };
  const auto drift = with("volume_drift");
  if (!drift.empty())
    emit(cx, overlay("ts_volume_drift", "Volume drift V/V0 - 1 vs t", "accuracy", "t",
                     "V / V_0 - 1", drift, t, {column("volume_drift", "V/V_0 - 1")}, false));
  const auto sheared = only(with("inclination_deg"), [](const Run& r) { return r.shear; });
  if (!sheared.empty())
    emit(cx,
         overlay("ts_inclination", "Inclination of the long axis vs t (simple shear)", "shear", "t",
                 "inclination (degrees)", sheared, t, {column("inclination_deg", "θ")}, false));
}

// D against Ca from the runs' steady states, with the small-deformation line D = slope * Ca of
// each distinct slope (the runs' law and flow) over [0, the largest Ca].
Figure steady_d_vs_ca(const std::vector<std::pair<Run, Table>>& data) {
  Figure fig = overlay("steady_D_vs_ca", "Steady Taylor deformation vs Ca", "figs. 16, 17", "Ca",
                       "D", data, column("ca"), {column("D")}, true);
  double ca_max = 0, d_max = 0;
  for (const Block& b : fig.blocks)
    for (const auto& row : b.rows) {
      ca_max = std::max(ca_max, row[0]);
      d_max = std::max(d_max, row[1]);
    }
  std::set<double> slopes;
  for (const auto& [run, tb] : data)
    if (run.small_deformation_slope > 0) slopes.insert(run.small_deformation_slope);
  int k = 0;
  for (double m : slopes) {
    // the asymptote of small Ca: drawn up to the data's largest D (x1.1), not across the plot
    const double ca_end = std::min(ca_max, 1.1 * d_max / m);
    char slope[32];
    std::snprintf(slope, sizeof slope, "%.3g", m);
    Block b;
    b.comment =
        "small-deformation theory (Barthes-Biesel & Rallison 1981): D = " + short_num(m) + " Ca";
    b.columns = {"ca", "D"};
    b.rows = {{0.0, 0.0}, {ca_end, m * ca_end}};
    Series s;
    s.block = static_cast<int>(fig.blocks.size());
    s.xcol = 1;
    s.ycol = 2;
    s.title = std::string("small deformation: D = ") + slope + " Ca";
    s.style = std::string("lines lw 1.5 lc rgb '#444444' dt ") + kDash[(k++ + 1) % 5];
    fig.blocks.push_back(std::move(b));
    fig.series.push_back(s);
  }
  return fig;
}

void steady_figures(Context& cx, const std::vector<Run>& runs) {
  const auto data =
      tables(cx, runs, "steady.csv",
             {"ca", "L", "S", "W", "Lc", "Sc", "Wc", "area", "edge_curvature", "tau_max"});
  if (data.empty()) return;
  const Quantity ca = column("ca"), lc = column("Lc");
  bool with_d = true;  // steady.csv files before D was a column lack it
  for (const auto& [run, tb] : data) with_d = with_d && tb.col("D") >= 0;
  if (with_d) emit(cx, steady_d_vs_ca(data));
  const Quantity ratio{"Sc_over_Wc", "Sc/Wc", [](const Table& t, long r) {
                         return t.num(r, t.col("Sc")) / t.num(r, t.col("Wc"));
                       }};
  const Quantity strain{"strain", "(Lc^2-1)/2", [](const Table& t, long r) {
                          const double l = t.num(r, t.col("Lc"));
                          return (l * l - 1) / 2;
                        }};
  emit(cx, overlay("steady_half_lengths_vs_ca", "Steady half-lengths L, S, W and Lc vs Ca",
                   "figs. 16, 17", "Ca", "half-length", data, ca,
                   {column("L"), column("S"), column("W"), column("Lc")}, true));
  emit(cx, overlay("steady_ScWc_vs_Lc", "Steady width Sc and depth Wc vs length Lc", "fig. 18a,b",
                   "Lc", "Sc, Wc", data, lc, {column("Sc"), column("Wc")}, true));
  emit(cx, overlay("steady_ScWc_ratio_vs_Lc", "Steady ratio Sc/Wc vs length Lc", "fig. 18c", "Lc",
                   "Sc/Wc", data, lc, {ratio}, true));
  emit(cx, overlay("steady_area_vs_ca", "Steady surface area vs Ca", "fig. 19a", "Ca", "area", data,
                   ca, {column("area")}, true));
  emit(cx, overlay("steady_area_vs_Lc", "Steady surface area vs length Lc", "fig. 19b", "Lc",
                   "area", data, lc, {column("area")}, true));
  Figure ec =
      overlay("steady_edge_curvature_vs_Lc", "Steady edge curvature vs length Lc", "fig. 20", "Lc",
              "edge curvature (log)", data, lc, {column("edge_curvature")}, true);
  ec.logy = true;
  for (auto& b : ec.blocks)  // log scale: only positive curvatures
    b.rows.erase(std::remove_if(b.rows.begin(), b.rows.end(),
                                [](const std::vector<double>& r) { return !(r[1] > 0); }),
                 b.rows.end());
  emit(cx, ec);
  emit(cx, overlay("steady_tau_max_vs_ca", "Steady maximum principal tension vs Ca", "fig. 21a",
                   "Ca", "τ_max / G_s", data, ca, {column("tau_max")}, true));
  emit(cx, overlay("steady_tau_max_vs_Lc", "Steady maximum principal tension vs length Lc",
                   "fig. 21b", "Lc", "τ_max / G_s", data, lc, {column("tau_max")}, true));
  emit(cx, overlay("steady_tau_max_vs_strain",
                   "Steady maximum principal tension vs strain indicator (Lc^2-1)/2", "fig. 22",
                   "(L_c^2 - 1)/2", "τ_max / G_s", data, strain, {column("tau_max")}, true));
}

// ---- profiles

Block unit_circle() {
  Block b;
  b.comment = "undisturbed profile: unit circle";
  b.columns = {"a", "b"};
  const int n = 200;
  for (int k = 0; k <= n; ++k) {
    const double th = 2 * M_PI * k / n;
    b.rows.push_back({std::cos(th), std::sin(th)});
  }
  return b;
}

Block profile_block(const figures::Profile& p, char plane, const std::string& label) {
  Block b;
  b.comment = label + "t = " + short_num(p.t) + ", plane " + plane + " = 0 (" + p.file +
              "; first point repeated to close the curve)";
  b.columns = {"a", "b"};
  const auto& pts = plane == 'z' ? p.z : p.y;
  for (const auto& [a, c] : pts) b.rows.push_back({a, c});
  if (!b.rows.empty()) b.rows.push_back(b.rows.front());
  return b;
}

// Indices into refs for the requested times (nearest, deduplicated, in time order); default:
// up to four evenly spaced profiles including the first and the last.
std::vector<size_t> pick(const std::vector<double>& ts, const std::vector<double>& want) {
  std::set<size_t> s;
  if (ts.empty()) return {};
  if (want.empty()) {
    const size_t n = ts.size(), k = std::min<size_t>(4, n);
    for (size_t i = 0; i < k; ++i) s.insert(k == 1 ? n - 1 : i * (n - 1) / (k - 1));
  } else {
    for (double t : want) s.insert(static_cast<size_t>(figures::nearest(ts, t)));
  }
  std::vector<size_t> v(s.begin(), s.end());
  std::sort(v.begin(), v.end(), [&](size_t a, size_t b) { return ts[a] < ts[b]; });
  return v;
}

void profile_figures(Context& cx, const std::vector<Run>& runs) {
  struct Last {
    Run run;
    figures::Profile p;
  };
  std::vector<Last> last;
  for (const auto& run : runs) {
    const auto refs = figures::list_profiles(run.dir);
    if (refs.empty()) {
      cx.note("run " + run.label + ": no profiles/profile_NNNNNN.csv, no profile figures");
      continue;
    }
    std::vector<double> ts;
    for (const auto& r : refs) ts.push_back(r.t);
    const auto chosen = pick(ts, cx.cmd.times);
    std::vector<figures::Profile> ps;
    for (size_t i : chosen) ps.push_back(figures::read_profile(refs[i].file));
    for (char plane : {'z', 'y'}) {
      Figure f;
      f.name = "profiles_" + safe_name(run.label) + "_" + plane;
      f.title = "Profile in the plane " + std::string(1, plane) + " = 0, run " + run.label;
      f.paper = plane == 'z' ? "figs. 6a, 7a, 12a" : "figs. 6b, 7b, 12b";
      f.xlabel = "x";
      f.ylabel = plane == 'z' ? "y" : "z";
      f.key = "outside right top";
      f.equal_aspect = true;
      f.blocks.push_back(unit_circle());
      f.series.push_back({0, 1, 2, "undisturbed", "lines lw 1 lc rgb '#808080' dt 2"});
      for (size_t k = 0; k < ps.size(); ++k) {
        f.blocks.push_back(profile_block(ps[k], plane, ""));
        f.series.push_back({static_cast<int>(k) + 1, 1, 2, "t = " + short_num(ps[k].t),
                            "lines lw 2 lc " + std::to_string(k % 8 + 1)});
        f.sources.push_back(ps[k].file);
      }
      for (double t : cx.cmd.times) {
        const long i = figures::nearest(ts, t);
        if (std::abs(ts[static_cast<size_t>(i)] - t) > 1e-9 * (1 + std::abs(t)))
          f.notes.push_back("requested t = " + short_num(t) + ": nearest available profile t = " +
                            short_num(ts[static_cast<size_t>(i)]));
      }
      emit(cx, f);
    }
    const double want = cx.cmd.times.empty() ? ts.back() : cx.cmd.times.back();
    last.push_back(
        {run, figures::read_profile(refs[static_cast<size_t>(figures::nearest(ts, want))].file)});
  }
  if (last.size() < 2) return;
  for (char plane : {'z', 'y'}) {
    Figure f;
    f.name = std::string("profiles_compare_") + plane;
    f.title = "Profiles of the runs compared, plane " + std::string(1, plane) + " = 0";
    f.paper = "fig. 15";
    f.xlabel = "x";
    f.ylabel = plane == 'z' ? "y" : "z";
    f.key = "outside right top";
    f.equal_aspect = true;
    f.blocks.push_back(unit_circle());
    f.series.push_back({0, 1, 2, "undisturbed", "lines lw 1 lc rgb '#808080' dt 3"});
    for (size_t k = 0; k < last.size(); ++k) {
      f.blocks.push_back(profile_block(last[k].p, plane, "run " + last[k].run.label + ", "));
      f.series.push_back({static_cast<int>(k) + 1, 1, 2,
                          last[k].run.label + " (t = " + short_num(last[k].p.t) + ")",
                          "lines lw 2 lc " + std::to_string(k % 8 + 1) + " dt " + kDash[k % 5]});
      f.sources.push_back(last[k].p.file);
    }
    emit(cx, f);
  }
}

// ---- 3-D views

// Frame PNGs of a run with their times: the time of frame N is that of profile N (written at
// the same step); without profiles, N * output.frame_every from control.json.
std::vector<std::pair<double, std::string>> frames_with_times(const Run& run, std::string* how) {
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

void view_figures(Context& cx, const std::vector<Run>& runs) {
  using namespace capflow::render;
  RenderOptions o;
  apply_render_flags(cx.cmd.view, &o);
  o.png = o.mp4 = false;
  std::optional<View> view;  // --view: instead of each run's camera
  if (!cx.cmd.view_name.empty()) {
    View v;
    if (!parse_view(cx.cmd.view_name, &v))
      throw UserError("--view: unknown '" + cx.cmd.view_name + "' (oblique | xy | xz | yz)");
    view = v;
    o.camera.view = v;
  }
  std::string err;
  if (!o.IsValid(&err)) throw UserError(err);
  // One renderer for every view: with the default colour range (render/color_range.h) the views
  // share one range that holds all of them, so one colour is one tension across the figures.
  std::unique_ptr<Renderer> renderer;
  std::string renderer_error;

  for (const auto& run : runs) {
    const auto surfaces = figures::list_surfaces(run.dir);
    std::string how;
    const auto frames = frames_with_times(run, &how);
    // --times; by default the run's final state (its newest checkpoint, else its last surface)
    std::vector<std::optional<double>> want(cx.cmd.times.begin(), cx.cmd.times.end());
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
      const std::string name = "view_" + safe_name(run.label) + "_" + time_tag(t_name);
      const bool elsewhere = t && std::abs(t_name - *t) > 1e-9 * (1 + std::abs(*t));
      if (elsewhere)
        cx.note(name + ": requested t = " + short_num(*t) +
                ", nearest saved state t = " + short_num(t_name));
      if (!done.insert(name).second) continue;
      const fs::path png = cx.out / (name + ".png");
      bool rendered = false;
      if (st) {
        if (!renderer && renderer_error.empty()) {
          try {
            renderer = std::make_unique<Renderer>(o);
          } catch (const std::exception& e) {
            renderer_error = e.what();
            cx.note("renderer unavailable (" + renderer_error + "): 3-D views fall back to frames");
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
          cx.manifest << "- **" << name << "**: 3-D view of run " << run.label
                      << " at t = " << short_num(s.time) << " (" << view_name(cam.view)
                      << " view), coloured by " << field_label(o.field)
                      << " (colour bar), rendered from " << st->note
                      << " (paper figs. 6c, 7c, 10). Files: " << name << ".png.\n";
          std::cerr << "figure: " << name << " (" << name
                    << ".png, rendered at t = " << short_num(s.time) << ")\n";
          cx.written.push_back(name);
          rendered = true;
        }
      }
      if (rendered) continue;
      if (frames.empty()) {
        cx.note(name + ": " + (note.empty() ? renderer_error : note) +
                " and no frames with known times; skipped");
        continue;
      }
      std::vector<double> ft;
      for (const auto& f : frames) ft.push_back(f.first);
      const auto& f = frames[static_cast<size_t>(figures::nearest(ft, t_name))];
      fs::copy_file(f.second, png, fs::copy_options::overwrite_existing);
      const std::string msg = name + ": NOT rendered at t = " + short_num(t_name) + " (" +
                              (note.empty() ? renderer_error : note) +
                              "): copied the nearest frame " + f.second +
                              " (t = " + short_num(f.first) + ", " + how + ")";
      cx.note(msg);
      cx.manifest << "- **" << name << "**: 3-D view of run " << run.label
                  << " from the saved frame nearest in time (see the note above). Files: " << name
                  << ".png.\n";
      std::cerr << "figure: " << name << " (" << name
                << ".png, from frame t = " << short_num(f.first) << ")\n";
      cx.written.push_back(name);
    }
  }
}

// A sweep directory (capflow sweep: sweep.csv and case_NNN/ run directories) given in place of a
// run stands for its cases, labelled by their values ("ca=0.3 capsule.C=1") from sweep.csv.
void expand_sweeps(FigureCmd* c) {
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
    std::ifstream in(csv);
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

int run(FigureCmd c) {
  expand_sweeps(&c);
  if (c.runs.empty()) throw UserError("give at least one run directory (or a sweep directory)");
  if (!c.labels.empty() && c.labels.size() != c.runs.size())
    throw UserError("--labels needs one label per run directory (" + std::to_string(c.runs.size()) +
                    ")");
  if (c.vector != "svg" && c.vector != "pdf") throw UserError("--vector: svg or pdf");
  const std::set<std::string> known{"timeseries", "profiles", "steady", "views"};
  for (const auto& k : c.kinds)
    if (!known.count(k))
      throw UserError("--kinds: unknown '" + k + "' (timeseries, profiles, steady, views)");
  std::vector<Run> runs;
  std::set<std::string> used;
  for (size_t i = 0; i < c.runs.size(); ++i) {
    if (!fs::is_directory(c.runs[i])) throw UserError("not a run directory: " + c.runs[i]);
    Run r;
    r.dir = c.runs[i];
    r.label = !c.labels.empty() ? c.labels[i]
                                : fs::path(c.runs[i]).lexically_normal().filename().string();
    if (r.label.empty() || r.label == ".")
      r.label = fs::absolute(c.runs[i]).lexically_normal().parent_path().filename().string();
    if (!used.insert(r.label).second) r.label += "_" + std::to_string(i + 1);
    try {
      const control::ControlOptions o =
          control::load_control_file((fs::path(r.dir) / "control.json").string()).options;
      r.law = membrane::to_string(o.law.kind);
      r.shear = o.flow.type == capsule::FlowType::SimpleShear;
      const double ks = o.law.kind == membrane::LawKind::Skalak ? 1 + 2 * o.law.c : 3.0;
      const double pe = 1.25 * (3 + 1 / ks);
      if (o.flow.type == capsule::FlowType::PlanarExtension) r.small_deformation_slope = pe;
      if (r.shear) r.small_deformation_slope = pe / 2;
    } catch (const std::exception&) {
    }
    runs.push_back(r);
  }

  Context cx;
  cx.cmd = c;
  cx.out = c.out;
  fs::create_directories(cx.out);
  cx.gnuplot = !c.no_gnuplot && has_gnuplot();
  cx.manifest << "# capflow figures\n\nWritten by `capflow figure` from:";
  for (const auto& r : runs) cx.manifest << " `" << r.dir << "` (" << r.label << ")";
  cx.manifest << ".\nEach 2-D figure has its gnuplot script `<name>.gp` and data `<name>.dat`; "
                 "edit the script and run `gnuplot <name>.gp` to restyle.\n\n";
  if (!c.no_gnuplot && !cx.gnuplot)
    cx.note(
        "gnuplot not found (apt-get install gnuplot-nox, or scripts/setup): wrote the .gp "
        "and .dat files only");
  auto want = [&](const char* k) {
    return std::find(c.kinds.begin(), c.kinds.end(), k) != c.kinds.end();
  };
  if (want("timeseries")) timeseries_figures(cx, runs);
  if (want("profiles")) profile_figures(cx, runs);
  if (want("steady")) steady_figures(cx, runs);
  if (want("views")) view_figures(cx, runs);
  write_text(cx.out / "figures.md", cx.manifest.str());
  std::cerr << "figure: " << cx.written.size() << " figures in " << cx.out.string()
            << " (list: figures.md)\n";
  if (cx.written.empty()) throw UserError("no figure could be made from the given runs");
  if (!c.no_gnuplot && !cx.gnuplot) return 1;
  return cx.failures ? 1 : 0;
}

void setup(CLI::App& root) {
  auto c = std::make_shared<FigureCmd>();
  CLI::App* sub = root.add_subcommand(
      "figure",
      "Figures from run directories: time series, profiles, steady-state curves (gnuplot\n"
      "scripts + data + SVG/PDF + PNG) and 3-D views (rendered from the saved surface\n"
      "nearest in time; from the nearest frame PNG when the run saved no surface).\n"
      "figures.md in the output directory lists what was made and from what.");
  sub->add_option(
         "runs", c->runs,
         "run directories (several: overlaid / compared), or a sweep directory (its cases)")
      ->required();
  sub->add_option("-o,--output", c->out, "output directory (created)");
  sub->add_option("--kinds", c->kinds, "timeseries,profiles,steady,views (default all)")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--times", c->times,
                  "T1,T2,...: times of profiles and 3-D views (nearest available); default "
                  "profiles: 4 spread over the run, views: the last saved time")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--labels", c->labels, "legend labels, one per run (default: directory names)")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--vector", c->vector, "vector format: svg | pdf");
  sub->add_flag("--no-png", c->no_png, "no PNG beside the vector image");
  sub->add_flag("--no-gnuplot", c->no_gnuplot, "write the .gp/.dat files without running gnuplot");
  add_render_flags(sub, &c->view, "3-D view ");
  sub->add_option("--view", c->view_name,
                  "3-D views from oblique | xy | xz | yz (default: each run's render.view)");
  sub->callback([c] { set_exit_code(run(*c)); });
}

}  // namespace

CAPFLOW_COMMAND(30, setup);

}  // namespace capflow::app
