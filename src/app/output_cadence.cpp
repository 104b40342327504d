#include "app/output_cadence.h"

#include <algorithm>
#include <cmath>

namespace capflow::app {

namespace {
// First multiple of `every` strictly after t (with a relative guard against round-off).
double next_after(double t, double every) {
  return every > 0 ? (std::floor(t / every + 1e-9) + 1.0) * every : INFINITY;
}
}  // namespace

void OutputCadence::reset_all(const control::OutputOptions& o, double t) {
  next_row_ = next_after(t, o.csv_every);
  next_frame_ = next_after(t, o.frame_every);
  next_vtk_ = next_after(t, o.vtk_every);
  next_checkpoint_ = next_after(t, o.checkpoint_every);
}

void OutputCadence::edit(const control::OutputOptions& b, const control::OutputOptions& a,
                         double t) {
  if (a.csv_every != b.csv_every) next_row_ = next_after(t, a.csv_every);
  if (a.frame_every != b.frame_every) next_frame_ = next_after(t, a.frame_every);
  if (a.vtk_every != b.vtk_every) next_vtk_ = next_after(t, a.vtk_every);
  if (a.checkpoint_every != b.checkpoint_every)
    next_checkpoint_ = next_after(t, a.checkpoint_every);
}

Due OutputCadence::due(double t, double dt) const {
  const double eps = 1e-9 * dt;
  Due d;
  d.row = t >= next_row_ - eps;
  d.frame = t >= next_frame_ - eps;
  d.vtk = t >= next_vtk_ - eps;
  d.checkpoint = t >= next_checkpoint_ - eps;
  return d;
}

double OutputCadence::next_time() const {
  return std::min({next_row_, next_frame_, next_vtk_, next_checkpoint_});
}

void OutputCadence::fired(const Due& d, const control::OutputOptions& o, double t) {
  if (d.row) next_row_ = next_after(t, o.csv_every);
  if (d.frame) next_frame_ = next_after(t, o.frame_every);
  if (d.vtk) next_vtk_ = next_after(t, o.vtk_every);
  if (d.checkpoint) next_checkpoint_ = next_after(t, o.checkpoint_every);
}

}  // namespace capflow::app
