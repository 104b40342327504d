// capflow/app/steady_outputs: see steady_outputs.h.
#include "app/steady_outputs.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "app/errors.h"
#include "app/format.h"
#include "app/frames.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "control/record.h"
#include "control/schedule.h"
#include "diagnostics/diagnostics.h"
#include "membrane/membrane.h"
#include "output/records.h"

namespace capflow::app {

using control::Record;

SteadyOutputs::SteadyOutputs(RunLifecycle& life, const control::ControlOptions& options,
                             const Grid& fine)
    : life_(life), opt_(options), fine_(fine) {}

void SteadyOutputs::write(const SteadyState& s) {
  const diagnostics::ShapeDiagnostics d =
      diagnostics::measure_shape(*fine_.mesh, fine_.x, diagnostics::ShapeOptions{});
  const membrane::MembraneFields f = fine_.cap->fields(fine_.x);
  const double tau_max = f.tension1.maxCoeff(), tau_min = f.tension2.minCoeff();
  const double drift = d.volume / fine_.cap->initial_volume() - 1.0;
  const capsule::SteadySolution& sol = *s.solution;
  life_.dir().steady().append(output::records::format_row(
      output::records::steady_solve(),
      {s.t, s.ca, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.area, d.edge_curvature, tau_max,
       tau_min, sol.residual, sol.speed, drift, static_cast<double>(s.newton),
       static_cast<double>(s.krylov), static_cast<double>(s.evaluations), s.wall_s,
       static_cast<double>(s.folds)}));
  std::ostringstream m;
  m << "steady state at Ca = " << s.ca << ": D = " << fixed(d.D, 6) << " L = " << fixed(d.L, 6)
    << " S = " << fixed(d.S, 6) << " W = " << fixed(d.W, 6) << " (" << s.evaluations
    << " velocity evaluations, " << fixed(s.wall_s, 1) << " s)";
  life_.say(m.str());
  warn_if_compressed(s.ca, tau_min, s.t);
  warn_if_oscillating(s.ca, oscillation(fine_), s.t);
  const std::string ckpt =
      write_checkpoint(s.ca, fine_.x, s.t, s.steps, "steady state by capflow steady");
  submit_frame(s.ca, s.t, d, tau_max, tau_min);
  life_.event(Record()
                  .set("event", "steady")
                  .set("ca", s.ca)
                  .set("D", d.D)
                  .set("L", d.L)
                  .set("residual", sol.residual)
                  .set("newton", s.newton)
                  .set("krylov", s.krylov)
                  .set("velocity_evaluations", s.evaluations)
                  .set("checkpoint", ckpt),
              s.t);
}

void SteadyOutputs::keep_last_good_state(double ca, long steps) {
  if (states_ > 0) {
    life_.say("last good state: the steady state of " +
              RunDirectory::checkpoints(life_.dir().path()).front().string());
    return;
  }
  const capsule::Capsule& cap = *fine_.cap;
  try {
    const std::string ckpt = write_checkpoint(
        ca, cap.positions(), cap.time(), steps,
        "the last good state of capflow steady's march to Ca = " + fixed(ca, 6) +
            " before it failed (not a steady state)");
    life_.say("last good state (t = " + fixed(cap.time(), 4) + ", not steady) kept in " + ckpt);
  } catch (const OutputError& e) {
    life_.say(std::string("the last good state could not be kept: ") + e.what());
  }
}

bool SteadyOutputs::frames_wanted() const {
  return opt_.output.png || opt_.output.mp4.enabled;
}

void SteadyOutputs::submit_frame(double ca, double t, const diagnostics::ShapeDiagnostics& d,
                                 double tau_max, double tau_min) {
  render::RenderThread* renderer = life_.renderer();
  if (!renderer) return;
  render::Snapshot sn = state_snapshot(*fine_.cap, fine_.x, t, ca,
                                       membrane::to_string(opt_.law.kind),
                                       {d.D, d.L, d.S, d.W, tau_max, tau_min});
  if (opt_.render.preview) renderer->offer_preview(sn);
  if (!frames_wanted()) return;
  sn.frame = frames_++;
  if (!renderer->submit_frame(std::move(sn)))
    throw OutputError("frames could not be written: " + renderer->error());
}

void SteadyOutputs::finish_frames() {
  if (!life_.renderer()) return;
  const render::RenderStats rs = life_.stop_renderer();
  if (frames_wanted())
    life_.say("renderer: " + std::to_string(frames_) + " frame" + (frames_ == 1 ? "" : "s") +
              " written, one per steady state" +
              (opt_.output.mp4.enabled ? " (" + std::to_string(rs.movie_frames) + " in the movie)"
                                       : std::string()));
}

void SteadyOutputs::warn(const std::string& cause, double ca, const char* key, double value,
                         const std::string& message, double t) {
  life_.say(message);
  life_.event(Record()
                  .set("event", "warning")
                  .set("cause", cause)
                  .set("ca", ca)
                  .set(key, value)
                  .set("message", message),
              t);
}

// A root with compressive tension somewhere: a membrane without bending stiffness wrinkles there
// at the scale of the mesh, so the shape is not resolved (below Ca ~ 0.15 in planar extension).
// With bending the compressed membrane has a finite wrinkle length and its shape is resolved
// unless the grid says otherwise (warn_if_oscillating).
void SteadyOutputs::warn_if_compressed(double ca, double tau_min, double t) {
  if (tau_min >= 0 || opt_.bending.enabled()) return;
  std::ostringstream m;
  m << "warning: compressive tension at the steady state at Ca = " << ca
    << " (tau_min = " << tau_min
    << "): the membrane wrinkles there (no bending stiffness), so this root is not a resolved "
       "steady shape";
  warn("compression", ca, "tau_min", tau_min, m.str(), t);
}

// A root with node-to-node oscillation above the time steps' failure limit: a march from it stops
// at its first step, and the grid does not resolve the shape.
void SteadyOutputs::warn_if_oscillating(double ca, double amplitude, double t) {
  const double limit = capsule::HealthOptions{}.oscillation_fail;
  if (amplitude <= limit) return;
  std::ostringstream m;
  m << "warning: node-to-node oscillation at the steady state at Ca = " << ca
    << " (highest-mode amplitude " << amplitude << " of the element size, above the time steps' "
    << "limit " << limit << "): NB=" << opt_.mesh.nb << " does not resolve this root (raise "
    << "mesh.nb)";
  warn("oscillation", ca, "amplitude", amplitude, m.str(), t);
}

// The state as a checkpoint of a run held at this Ca.
std::string SteadyOutputs::write_checkpoint(double ca, const Eigen::Matrix3Xd& x, double t,
                                            long steps, const std::string& note) {
  RunCheckpoint c;
  c.options = opt_;
  c.options.ca = control::CaSchedule{};
  control::CaSegment hold;
  hold.ca = ca;
  c.options.ca.segments.push_back(hold);
  c.options.time.t_end = std::max(opt_.time.t_end, t + 1.0);
  c.control = control::to_json_text(c.options);
  c.control_file = c.control;
  c.x = x;
  c.t = t;
  c.steps = steps;
  c.ca = ca;
  c.schedule = control::CaScheduler(c.options.ca, c.options.steady, t, ca).state();
  const capsule::HealthMonitor h(*fine_.mesh, x);
  c.health_normals = h.normals();
  c.health_flags = h.flags();
  c.wall_s = life_.wall();
  c.note = note;
  return life_.store_checkpoint([&] { return c; }, ++states_).string();
}

}  // namespace capflow::app
