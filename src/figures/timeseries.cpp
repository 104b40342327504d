// capflow/figures/timeseries: the time-series kinds (kinds.h), from each run's timeseries.csv.
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "figures/format.h"
#include "figures/kinds.h"
#include "figures/labels.h"
#include "figures/references.h"
#include "figures/style.h"

namespace capflow::figures {

namespace fs = std::filesystem;
using labels::it;

std::vector<RunTable> load_run_tables(Writer& w, const std::vector<RunInfo>& runs,
                                      const output::records::Layout& layout,
                                      const std::vector<std::string>& need) {
  // the columns the figures read are the run's (output/records.h): a name it does not write is
  // a bug here, not a run's fault
  for (const auto& c : need) layout.index(c);
  const std::string file = layout.file;
  std::vector<RunTable> out;
  for (const auto& r : runs) {
    const fs::path p = fs::path(r.dir) / file;
    if (!fs::exists(p)) {
      w.note("run " + r.label + ": no " + file + ", left out of the " + file + " figures");
      continue;
    }
    try {
      Table t = read_csv(p.string());
      for (const auto& c : need)
        if (t.col(c) < 0) throw std::runtime_error(p.string() + ": no column '" + c + "'");
      out.emplace_back(r, std::move(t));
    } catch (const std::exception& e) {
      w.note("run " + r.label + ": " + e.what() + "; left out");
    }
  }
  return out;
}

namespace {

// Below this Taylor deformation the long axis (the inclination) is not defined to plot.
constexpr double kRoundShape = 1e-3;

template <class Keep>
std::vector<RunTable> only(const std::vector<RunTable>& data, Keep keep) {
  std::vector<RunTable> out;
  for (const auto& d : data)
    if (keep(d.first)) out.push_back(d);
  return out;
}

// The paper's steady D as a line over the run's time span, for each run that ends at a Ca the
// paper reports for its law and flow.
void add_published_steady_d(Figure* fig, const std::vector<RunTable>& data) {
  int k = 0;
  for (const auto& [run, tb] : data) {
    if (tb.rows() == 0) continue;
    const double ca = tb.num(tb.rows() - 1, tb.col("ca"));
    const double t0 = tb.num(0, tb.col("t")), t1 = tb.num(tb.rows() - 1, tb.col("t"));
    for (const PublishedSteady& p : published_steady(run)) {
      // (a run without a ca column has NaN here: no line)
      if (!p.paper || !(std::abs(p.ca - ca) <= 1e-9)) continue;
      Block b;
      b.comment = p.source + ": steady D at Ca = " + short_num(p.ca) + " (run " + run.label + ")";
      b.columns = {"t", "D"};
      b.rows = {{t0, p.D}, {t1, p.D}};
      Series s;
      s.block = static_cast<int>(fig->blocks.size());
      s.title = "paper, steady " + it("D") + " at Ca = " + short_num(p.ca);
      s.style = style::theory_line(k++);
      fig->blocks.push_back(std::move(b));
      fig->panels[0].series.push_back(s);
    }
  }
}

}  // namespace

void timeseries_figures(Writer& w, const std::vector<RunInfo>& runs, const KindOptions& o) {
  const auto data = load_run_tables(
      w, runs, output::records::timeseries(), {"t", "D", "L", "S", "W", "edge_curvature", "tau_max", "tau_min"});
  if (data.empty()) return;
  const Quantity t = column("t");
  Figure d = overlay({"ts_D", "Taylor deformation D against time", "figs. 5a, 11a", labels::time(),
                      labels::deformation()},
                     data, t, {column("D")});
  if (o.references && has_rows(d)) add_published_steady_d(&d, data);
  w.emit(d);
  w.emit(overlay({"ts_LSW", "Half-lengths L, S, W of the inertia ellipsoid against time",
                  "figs. 5, 11", labels::time(), labels::half_lengths()},
                 data, t, {column("L", it("L")), column("S", it("S")), column("W", it("W"))}));
  // the +x tip's curvature means nothing for a tank-treading (shear) capsule
  const auto straining = only(data, [](const RunInfo& r) { return !r.shear(); });
  if (!straining.empty())
    w.emit(overlay({"ts_edge_curvature", "Edge curvature (z = 0 profile, +x tip) against time",
                    "figs. 8, 13", labels::time(), labels::curvature()},
                   straining, t, {column("edge_curvature")}));
  w.emit(overlay({"ts_tension", "Largest and smallest principal tensions against time",
                  "figs. 9, 14", labels::time(), labels::tension()},
                 data, t,
                 {column("tau_max", it("τ") + "_{max}"), column("tau_min", it("τ") + "_{min}")}));
  // D(t) over Ca(t): what a steered run was driven with, under what it did
  bool have_ca = true;
  for (const auto& [run, tb] : data) have_ca = have_ca && tb.col("ca") >= 0;
  if (have_ca) {
    Figure dc = overlay({"ts_D_ca",
                         "Taylor deformation D (top) and the capillary number Ca it was driven "
                         "with (bottom) against time",
                         "", labels::time(), labels::deformation()},
                        data, t, {column("D")});
    add_panel(&dc, data, t, column("ca"), labels::capillary());
    w.emit(dc);
  }
  // the runs that have the column (older runs lack it: left out with a note)
  const auto with = [&](const std::string& c) {
    return load_run_tables(w, runs, output::records::timeseries(), {"t", c});
  };
  const auto drift = with("volume_drift");
  if (!drift.empty())
    w.emit(overlay({"ts_volume_drift", "Relative volume change against time", "", labels::time(),
                    labels::volume_drift()},
                   drift, t, {column("volume_drift")}));
  const auto sheared =
      only(load_run_tables(w, runs, output::records::timeseries(), {"t", "D", "inclination_deg"}),
           [](const RunInfo& r) { return r.shear(); });
  // a nearly spherical shape has no long axis: its rows (the start from rest) are left out
  const Quantity inclination{"inclination_deg", it("θ"), [](const Table& tb, long r) {
                               return std::abs(tb.num(r, tb.col("D"))) < kRoundShape
                                          ? std::numeric_limits<double>::quiet_NaN()
                                          : tb.num(r, tb.col("inclination_deg"));
                             }};
  if (!sheared.empty())
    w.emit(
        overlay({"ts_inclination",
                 "Inclination of the long axis to the flow direction against time (simple shear)",
                 "", labels::time(), labels::inclination()},
                sheared, t, {inclination}));
}

}  // namespace capflow::figures
