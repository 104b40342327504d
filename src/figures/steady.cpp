// capflow/figures/steady: the steady-state kinds (kinds.h), from each run's steady.csv (one row
// per steady state reached: `hold: steady` in a run, or `capflow steady`).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "figures/format.h"
#include "figures/kinds.h"
#include "figures/labels.h"
#include "figures/references.h"
#include "figures/style.h"

namespace capflow::figures {

using labels::it;

namespace {

// The Ca range of the figure's data blocks (the runs' rows).
std::pair<double, double> ca_range(const Figure& fig, size_t run_blocks) {
  double lo = INFINITY, hi = -INFINITY;
  for (size_t b = 0; b < run_blocks; ++b)
    for (const auto& row : fig.blocks[b].rows) {
      lo = std::min(lo, row[0]);
      hi = std::max(hi, row[0]);
    }
  return {lo, hi};
}

// The small-deformation line D = slope Ca of each distinct slope among the runs, from 0 up to
// the data's largest D (x1.1): the asymptote of small Ca, not drawn across the plot.
void add_small_deformation_lines(Figure* fig, const std::vector<RunTable>& data) {
  double ca_max = 0, d_max = 0;
  for (size_t b = 0; b < data.size(); ++b)
    for (const auto& row : fig->blocks[b].rows) {
      ca_max = std::max(ca_max, row[0]);
      d_max = std::max(d_max, row[1]);
    }
  std::set<double> slopes;
  for (const auto& d : data)
    if (const double m = small_deformation_slope(d.first); m > 0) slopes.insert(m);
  int k = 0;
  for (double m : slopes) {
    const double ca_end = std::min(ca_max, 1.1 * d_max / m);
    Block b;
    b.comment =
        "small-deformation theory (Barthes-Biesel & Rallison 1981): D = " + exact_num(m) + " Ca";
    b.columns = {"ca", "D"};
    b.rows = {{0.0, 0.0}, {ca_end, m * ca_end}};
    Series s;
    s.block = static_cast<int>(fig->blocks.size());
    char slope[32];
    std::snprintf(slope, sizeof slope, "%.3g", m);
    s.title = std::string("small deformation: ") + it("D") + " = " + slope + " Ca";
    s.style = style::theory_line(k++);
    fig->blocks.push_back(std::move(b));
    fig->panels[0].series.push_back(s);
  }
}

// The published steady states of the runs' laws and flows inside the data's Ca range (+-10 %):
// one block and marker per source, column `value` picked from (D, L).
void add_published(Figure* fig, const std::vector<RunTable>& data, bool length) {
  const auto [lo, hi] = ca_range(*fig, data.size());
  std::map<std::string, Block> by_source;
  std::set<std::pair<std::string, double>> seen;
  for (const auto& d : data)
    for (const PublishedSteady& p : published_steady(d.first)) {
      if (p.ca < 0.9 * lo || p.ca > 1.1 * hi || !seen.insert({p.source, p.ca}).second) continue;
      Block& b = by_source[p.source];
      b.comment = p.source + ": published steady states (quoted in the paper)";
      b.columns = {"ca", length ? "L" : "D"};
      b.rows.push_back({p.ca, length ? p.L : p.D});
    }
  int k = 0;
  for (auto& [source, b] : by_source) {
    Series s;
    s.block = static_cast<int>(fig->blocks.size());
    s.title = labels::literal(source);
    s.style = style::published_points(k++);
    fig->blocks.push_back(std::move(b));
    fig->panels[0].series.push_back(s);
  }
}

}  // namespace

void steady_figures(Writer& w, const std::vector<RunInfo>& runs, const KindOptions& o) {
  const auto data =
      load_run_tables(w, runs, output::records::steady_run(),
                      {"ca", "L", "S", "W", "Lc", "Sc", "Wc", "area", "edge_curvature", "tau_max"});
  if (data.empty()) return;
  const Quantity ca = column("ca"), lc = column("Lc");
  const std::string lc_label = it("L") + "_c / " + it("a");
  bool with_d = true;  // steady.csv files before D was a column lack it
  for (const auto& [run, tb] : data) with_d = with_d && tb.col("D") >= 0;
  if (with_d) {
    Figure d = overlay({"steady_D_vs_ca", "Steady Taylor deformation D against Ca", "figs. 16, 17",
                        labels::capillary(), labels::deformation(), true},
                       data, ca, {column("D")});
    if (o.references && has_rows(d)) {
      add_small_deformation_lines(&d, data);
      add_published(&d, data, false);
    }
    w.emit(d);
  }
  Figure half = overlay(
      {"steady_half_lengths_vs_ca",
       "Steady half-lengths L, S, W (inertia ellipsoid) and Lc (profile) against Ca",
       "figs. 16, 17", labels::capillary(),
       it("L") + ", " + it("S") + ", " + it("W") + ", " + it("L") + "_c / " + it("a"), true},
      data, ca,
      {column("L", it("L")), column("S", it("S")), column("W", it("W")),
       column("Lc", it("L") + "_c")});
  if (o.references && has_rows(half)) add_published(&half, data, true);
  w.emit(half);
  const Quantity ratio{
      "Sc_over_Wc", it("S") + "_c / " + it("W") + "_c",
      [](const Table& t, long r) { return t.num(r, t.col("Sc")) / t.num(r, t.col("Wc")); }};
  const Quantity strain{"strain", "(" + it("L") + "_c^2 − 1) / 2", [](const Table& t, long r) {
                          const double l = t.num(r, t.col("Lc"));
                          return (l * l - 1) / 2;
                        }};
  w.emit(overlay({"steady_ScWc_vs_Lc", "Steady width Sc and depth Wc against length Lc",
                  "fig. 18a,b", lc_label, it("S") + "_c, " + it("W") + "_c / " + it("a"), true},
                 data, lc, {column("Sc", it("S") + "_c"), column("Wc", it("W") + "_c")}));
  w.emit(overlay({"steady_ScWc_ratio_vs_Lc", "Steady ratio Sc/Wc against length Lc", "fig. 18c",
                  lc_label, ratio.label, true},
                 data, lc, {ratio}));
  w.emit(overlay({"steady_area_vs_ca", "Steady surface area against Ca", "fig. 19a",
                  labels::capillary(), labels::area(), true},
                 data, ca, {column("area")}));
  w.emit(overlay({"steady_area_vs_Lc", "Steady surface area against length Lc", "fig. 19b",
                  lc_label, labels::area(), true},
                 data, lc, {column("area")}));
  Figure ec = overlay({"steady_edge_curvature_vs_Lc", "Steady edge curvature against length Lc",
                       "fig. 20", lc_label, labels::curvature(), true},
                      data, lc, {column("edge_curvature")});
  ec.panels[0].logy = true;
  for (auto& b : ec.blocks)  // log scale: only positive curvatures
    b.rows.erase(std::remove_if(b.rows.begin(), b.rows.end(),
                                [](const std::vector<double>& r) { return !(r[1] > 0); }),
                 b.rows.end());
  w.emit(ec);
  const std::string tmax = it("τ") + "_{max} / " + it("G") + "_s";
  w.emit(overlay({"steady_tau_max_vs_ca", "Steady largest principal tension against Ca", "fig. 21a",
                  labels::capillary(), tmax, true},
                 data, ca, {column("tau_max")}));
  w.emit(overlay({"steady_tau_max_vs_Lc", "Steady largest principal tension against length Lc",
                  "fig. 21b", lc_label, tmax, true},
                 data, lc, {column("tau_max")}));
  w.emit(overlay({"steady_tau_max_vs_strain",
                  "Steady largest principal tension against the strain indicator (Lc² − 1)/2",
                  "fig. 22", strain.label, tmax, true},
                 data, strain, {column("tau_max")}));
}

}  // namespace capflow::figures
