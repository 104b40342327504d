// capflow/figures/tank_treading: ts_tank_treading, the membrane's turning in simple shear from a
// run's ParaView surfaces (surface.pvd, written when output.vtk_every > 0).
//
// A surface's grid points are material points (fixed element parameters of the interpolant
// through the material nodes), written in the same order at every time. The figure follows the
// point highest in z on the first surface (on the rim of a red cell whose axis lies along the
// flow; the pole of a sphere): its angle about the centroid in the shear plane, from +x towards
// +z like the inclination, unwrapped over time (the centroid: the mean of the grid points, exact
// for the mesh's point-symmetric grids). A tank-treading membrane turns steadily while the shape
// keeps its inclination; a tumbling capsule turns its shape with it. The phase's mean rate over
// the run is stated in figures.md (a full turn is -360 degrees: the shear turns clockwise), and,
// once the point has made a full turn, the duration T of its last one: the tank-treading period
// of a tank-treading or swinging cell (the tumbling period of a tumbling one), whose frequency
// f = 1/T the experiments report as f / G or 4 pi f / G (1 for a rigid sphere's G / 2 spin).
#include <cmath>
#include <filesystem>
#include <sstream>

#include "figures/format.h"
#include "figures/kinds.h"
#include "figures/labels.h"
#include "figures/style.h"
#include "output/vtk.h"

namespace capflow::figures {

namespace {

constexpr double kDegrees = 180.0 / M_PI;

// The angle (degrees) of grid point k about the grid's mean, in the x-z plane.
double phase_of(const output::VtkSurface& s, long k) {
  double xc = 0, zc = 0;
  const long n = s.num_points();
  for (long i = 0; i < n; ++i) {
    xc += s.x[3 * i];
    zc += s.x[3 * i + 2];
  }
  xc /= static_cast<double>(n);
  zc /= static_cast<double>(n);
  return std::atan2(s.x[3 * k + 2] - zc, s.x[3 * k] - xc) * kDegrees;
}

// The highest grid point (largest z).
long highest_point(const output::VtkSurface& s) {
  long best = 0;
  for (long i = 1; i < s.num_points(); ++i)
    if (s.x[3 * i + 2] > s.x[3 * best + 2]) best = i;
  return best;
}

// t and the unwrapped phase of one material point over a run's surfaces; false (with a note)
// when the run has fewer than two readable surfaces on one grid.
bool phase_series(Writer& w, const RunInfo& run, Block* block) {
  const std::string pvd = (std::filesystem::path(run.dir) / "surface.pvd").string();
  if (!std::filesystem::exists(pvd)) {
    w.note(run.dir + ": no surface.pvd (output.vtk_every > 0 writes it): no tank-treading phase");
    return false;
  }
  long point = -1, points = 0;
  double last = 0, turns = 0;
  for (const output::PvdEntry& e : output::PvdCollection::read(pvd)) {
    const std::string file = (std::filesystem::path(pvd).parent_path() / e.file).string();
    output::VtkSurface s;
    try {
      s = output::read_vtp(file);
    } catch (const std::exception& ex) {
      w.note(file + ": " + ex.what() + " (left out of the tank-treading phase)");
      continue;
    }
    if (point < 0) {
      point = highest_point(s);
      points = s.num_points();
    } else if (s.num_points() != points) {
      w.note(file + ": another grid than the first surface's (left out of the tank-treading "
                    "phase)");
      continue;
    }
    double phase = phase_of(s, point) + 360 * turns;
    if (!block->rows.empty()) {
      while (phase - last > 180) phase -= 360, turns -= 1;
      while (phase - last < -180) phase += 360, turns += 1;
    }
    last = phase;
    block->rows.push_back({e.time, phase});
  }
  if (block->rows.size() < 2) {
    w.note(run.dir + ": fewer than two surfaces: no tank-treading phase");
    return false;
  }
  return true;
}

// The duration of the last full turn (360 degrees of phase, either way) that ends at the last
// row, the start interpolated linearly between rows; 0 when the phase has not made a full turn.
// Sets *start to the turn's start time.
double last_turn_period(const Block& b, double* start) {
  const std::vector<double>& end = b.rows.back();
  for (size_t i = b.rows.size() - 1; i-- > 0;) {
    const double d0 = std::abs(b.rows[i][1] - end[1]), d1 = std::abs(b.rows[i + 1][1] - end[1]);
    if (d0 >= 360 && d1 < 360) {
      *start = b.rows[i][0] + (b.rows[i + 1][0] - b.rows[i][0]) * (d0 - 360) / (d0 - d1);
      return end[0] - *start;
    }
  }
  return 0;
}

}  // namespace

void tank_treading_figures(Writer& w, const std::vector<RunInfo>& runs) {
  Figure f;
  f.name = "ts_tank_treading";
  f.caption =
      "Phase of a membrane point about the centroid in the shear plane against time (simple "
      "shear, from the ParaView surfaces)";
  f.xlabel = labels::time();
  f.panels[0].ylabel = "phase " + labels::it("φ") + " / deg";
  int colour = 0;
  for (const RunInfo& run : runs) {
    if (!run.shear()) continue;
    Block b;
    b.comment =
        run.dir + ": t, the unwrapped phase (deg) of the highest point of the first surface";
    b.columns = {"t", "phase_deg"};
    if (!phase_series(w, run, &b)) continue;
    const double rate =
        (b.rows.back()[1] - b.rows.front()[1]) / (b.rows.back()[0] - b.rows.front()[0]);
    std::ostringstream m;
    m << run.dir << ": the membrane point turns at " << short_num(rate) << " deg per unit G t ("
      << short_num(rate / 360) << " turns) from t = " << short_num(b.rows.front()[0]) << " to "
      << short_num(b.rows.back()[0]);
    double start = 0;
    if (const double period = last_turn_period(b, &start); period > 0)
      m << "; its last full turn, from t = " << short_num(start) << ", took T G = "
        << short_num(period) << ": f / G = " << short_num(1 / period)
        << ", 4 pi f / G = " << short_num(4 * M_PI / period);
    f.notes.push_back(m.str());
    f.sources.push_back((std::filesystem::path(run.dir) / "surface.pvd").string());
    f.blocks.push_back(std::move(b));
    f.panels[0].series.push_back(Series{static_cast<int>(f.blocks.size()) - 1, 1, 2, run.label,
                                        style::data_line(colour, 0, colour, false)});
    ++colour;
  }
  if (!f.blocks.empty()) w.emit(f);
}

}  // namespace capflow::figures
