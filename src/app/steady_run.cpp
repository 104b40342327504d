#include "app/steady_run.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "app/errors.h"
#include "app/run_checkpoint.h"
#include "app/run_directory.h"
#include "app/run_log.h"
#include "capsule/adaptive_stepper.h"
#include "capsule/capsule.h"
#include "capsule/health.h"
#include "capsule/steady_solver.h"
#include "control/control_file.h"
#include "control/record.h"
#include "control/schedule.h"
#include "diagnostics/diagnostics.h"
#include "geometry/surface.h"
#include "membrane/membrane.h"

namespace capflow::app {

namespace fs = std::filesystem;
using control::Record;

int SteadySummary::exit_code() const {
  if (output_failed) return exit_code::kOutputFailed;
  if (failed) return exit_code::kSimulationFailed;
  return exit_code::kOk;
}

namespace {

constexpr double kApproachSpeed = 2e-2;   // largest node speed (a G) that ends the approach
constexpr double kMapStepFactor = 0.7;    // RK4 map step / adaptive (Cash-Karp) steps
constexpr double kMaxApproachTime = 400;  // simulated time the approach may take per level
constexpr int kSolveAttempts = 3;

const char* const kTimeseriesHeader =
    "t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,inclination_deg,"
    "volume_drift,steps,dt,wall_s\n";
const char* const kSteadyHeader =
    "t,ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min,residual,speed,volume_drift,"
    "newton,krylov,evaluations,wall_s\n";

// The levels of Ca the control file asks for.
std::vector<double> levels_of(const control::CaSchedule& s) {
  std::vector<double> out;
  double level = 0;
  for (const control::CaSegment& g : s.segments) {
    switch (g.kind) {
      case control::CaSegment::Kind::Hold:
        out.push_back(level = g.ca);
        break;
      case control::CaSegment::Kind::Steps: {
        const double dir = g.to >= level ? 1.0 : -1.0;
        while (std::abs(g.to - level) > 1e-12 * std::max(1.0, g.to)) {
          level = std::abs(g.to - level) <= g.by * (1 + 1e-12) ? g.to : level + dir * g.by;
          out.push_back(level);
        }
        break;
      }
      case control::CaSegment::Kind::Ramp:
        throw UserError(
            "ca: capflow steady solves at levels of Ca; a ramp has none (give a number, a list "
            "of {\"ca\": x} levels, or {\"steps\": {\"to\": ..., \"by\": ...}})");
    }
  }
  return out;
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

class SteadyRun {
 public:
  SteadyRun(const control::ControlOptions& o, bool overwrite) : opt_(o) {
    if (!capsule::is_pure_straining(o.flow.gradient))
      throw UserError(
          "flow.type: capflow steady needs a pure straining flow (a symmetric flow.gradient: "
          "planar, uniaxial or biaxial extension). In " +
          o.flow.name() +
          " a steady capsule's membrane keeps moving (tank-treading), so its shape is not a "
          "root of the node velocities: use capflow run with \"steady\": {\"stop\": true}");
    levels_ = levels_of(o.ca);
    if (levels_.empty()) throw UserError("ca: no level to solve at");
    if (o.output.dir.empty()) throw UserError("output.dir: give a run directory (or -o DIR)");
    dir_ = RunDirectory::open(
        o.output.dir, overwrite ? RunDirectory::Mode::Overwrite : RunDirectory::Mode::Create);
    dir_->open_records(true, kTimeseriesHeader, kSteadyHeader);
    log_ = std::make_unique<RunLog>(*dir_, isatty(STDERR_FILENO));
    dir_->write_text("control.json", control::to_json_text(opt_));
    mesh_ = control::make_mesh(o.mesh);
    cap_ = std::make_unique<capsule::Capsule>(*mesh_, o.law, o.flow, control::dynamics_options(o));
    x_ = cap_->positions();
    if (!o.start.from.empty()) start_from();
  }

  SteadySummary run(const std::atomic<bool>* stop) {
    SteadySummary sum;
    announce();
    for (size_t i = 0; i < levels_.size(); ++i) {
      if (stop && stop->load()) {
        say("stopped by signal before Ca = " + fixed(levels_[i], 6));
        break;
      }
      const bool ok = solve_level(levels_[i], stop);
      if (!ok) {
        sum.failed = true;
        sum.failure = failure_;
        break;
      }
      ++sum.states;
    }
    sum.wall_s = wall();
    sum.evaluations = cap_->velocity_evaluations();
    std::ostringstream m;
    m << "end: " << sum.states << " steady state" << (sum.states == 1 ? "" : "s") << " of "
      << levels_.size() << ", " << sum.evaluations << " velocity evaluations, wall "
      << fixed(sum.wall_s, 1) << " s" << (sum.failed ? " (" + sum.failure + ")" : "");
    say(m.str());
    log_->event(Record()
                    .set("event", "end")
                    .set("states", sum.states)
                    .set("exit_code", sum.exit_code())
                    .set("velocity_evaluations", sum.evaluations)
                    .set("wall_s", sum.wall_s),
                t_);
    return sum;
  }

 private:
  double wall() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  void say(const std::string& s) { log_->say(s); }

  void announce() {
    std::ostringstream m;
    m << "capflow steady: " << membrane::to_string(opt_.law.kind) << ", " << opt_.flow.name()
      << ", NE=" << opt_.mesh.elements << " NB=" << opt_.mesh.nb << ", " << levels_.size()
      << " level" << (levels_.size() == 1 ? "" : "s") << " of Ca from " << levels_.front() << " to "
      << levels_.back() << ", symmetry targets " << cap_->symmetry().targets().size() << " -> "
      << dir_->path().string();
    say(m.str());
    log_->event(Record().set("event", "start").set_json("control", control::to_json_text(opt_)),
                t_);
  }

  void start_from() {
    const RunCheckpoint src = read_latest_checkpoint(opt_.start.from);
    Eigen::Matrix3Xd x = geometry::resample_surface(*src.mesh, src.x, *mesh_);
    if (!x.allFinite())
      throw UserError(src.path + ": the stored shape does not resample to a finite one");
    x_ = capsule::rescale_to_volume(*mesh_, x, cap_->initial_volume());
    say("initial shape from " + src.path + " (Ca = " + std::to_string(src.ca) + ")");
  }

  // Adaptive time steps at Ca = ca from x_ until the node speed is below `speed`. Returns the
  // median of the last accepted steps (0 when none), or -1 when the march failed.
  double approach(double ca, double speed, const std::atomic<bool>* stop) {
    capsule::AdaptiveOptions ao;
    ao.tolerance = opt_.time.tolerance;
    capsule::AdaptiveStepper st(
        [&](double, const Eigen::VectorXd& y, Eigen::VectorXd* d) {
          const Eigen::Matrix3Xd u =
              cap_->velocity(Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, y.size() / 3), ca);
          *d = Eigen::Map<const Eigen::VectorXd>(u.data(), u.size());
        },
        ao);
    capsule::HealthMonitor health(*mesh_, x_);
    Eigen::VectorXd y = Eigen::Map<const Eigen::VectorXd>(x_.data(), x_.size());
    st.restart(t_, y, h_last_);
    const double t0 = t_;
    std::vector<double> steps;
    double v = std::numeric_limits<double>::infinity();
    while (v > speed) {
      if ((stop && stop->load()) || t_ - t0 > kMaxApproachTime) break;
      const Eigen::VectorXd before = y;
      capsule::AdaptiveStepper::Step s;
      try {
        s = st.step(
            t_ + 1.0,
            [&](Eigen::VectorXd* z) {
              Eigen::Map<Eigen::Matrix3Xd> xz(z->data(), 3, z->size() / 3);
              Eigen::Matrix3Xd xf = xz;
              cap_->finish_step(&xf);
              xz = xf;
            },
            [&](const Eigen::VectorXd& z, double t) {
              const capsule::HealthReport r =
                  health.check(Eigen::Map<const Eigen::Matrix3Xd>(z.data(), 3, z.size() / 3), t);
              return r.level == capsule::HealthLevel::Failure ? r.message : std::string();
            },
            &y);
      } catch (const capsule::StepFailure& e) {
        failure_ = e.what();
        return -1;
      }
      t_ = s.t;
      ++steps_;
      v = (y - before).cwiseAbs().maxCoeff() / s.h;
      steps.push_back(s.h);
    }
    x_ = Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, y.size() / 3);
    if (steps.empty()) return h_last_;
    const size_t n = std::min<size_t>(steps.size(), 10);
    std::vector<double> last(steps.end() - n, steps.end());
    std::sort(last.begin(), last.end());
    h_last_ = last[n / 2];
    return h_last_;
  }

  bool solve_level(double ca, const std::atomic<bool>* stop) {
    const auto t_level = std::chrono::steady_clock::now();
    const long evals0 = cap_->velocity_evaluations();
    double speed = kApproachSpeed;
    capsule::SteadySolution sol;
    int newton = 0;
    long krylov = 0;
    for (int attempt = 0; attempt < kSolveAttempts; ++attempt, speed /= 4) {
      const double h = approach(ca, speed, stop);
      if (h < 0) return fail(ca, "the approach failed: " + failure_);
      if (stop && stop->load()) return fail(ca, "stopped by signal during the approach");
      capsule::SteadySolveOptions so;
      so.step = kMapStepFactor * h;
      so.tolerance = opt_.steady.solve_tolerance;
      sol = capsule::solve_steady(*cap_, x_, ca, so);
      newton += sol.newton;
      krylov += sol.krylov;
      std::ostringstream m;
      m << "Ca = " << ca << ": Newton " << (sol.converged ? "converged" : "did not converge")
        << " (" << sol.message << ") in " << sol.newton << " iterations, " << sol.krylov
        << " GMRES iterations, residual " << std::scientific << std::setprecision(2) << sol.residual
        << " (map step " << so.step << ", approach to t = " << std::defaultfloat << t_ << ")";
      say(m.str());
      if (sol.converged) break;
    }
    if (!sol.converged)
      return fail(ca, "no steady state found: " + sol.message + ", residual " +
                          std::to_string(sol.residual));
    x_ = sol.x;
    write_state(ca, sol, newton, krylov, cap_->velocity_evaluations() - evals0,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t_level).count());
    return true;
  }

  bool fail(double ca, const std::string& why) {
    failure_ = "Ca = " + std::to_string(ca) + ": " + why;
    say("failure: " + failure_);
    log_->event(Record().set("event", "failure").set("ca", ca).set("message", failure_), t_);
    return false;
  }

  void write_state(double ca, const capsule::SteadySolution& sol, int newton, long krylov,
                   long evaluations, double wall_s) {
    diagnostics::ShapeOptions so;
    const diagnostics::ShapeDiagnostics d = diagnostics::measure_shape(*mesh_, x_, so);
    const membrane::MembraneFields f = cap_->fields(x_);
    const double drift = d.volume / cap_->initial_volume() - 1.0;
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,"
                  "%.3e,%.3e,%.3e,%d,%ld,%ld,%.3f\n",
                  t_, ca, d.L, d.S, d.W, d.Lc, d.Sc, d.Wc, d.D, d.area, d.edge_curvature,
                  f.tension1.maxCoeff(), f.tension2.minCoeff(), sol.residual, sol.speed, drift,
                  newton, krylov, evaluations, wall_s);
    dir_->steady().append(buf);
    std::ostringstream m;
    m << "steady state at Ca = " << ca << ": D = " << fixed(d.D, 6) << " L = " << fixed(d.L, 6)
      << " S = " << fixed(d.S, 6) << " W = " << fixed(d.W, 6) << " (" << evaluations
      << " velocity evaluations, " << fixed(wall_s, 1) << " s)";
    say(m.str());
    const std::string ckpt = write_checkpoint(ca);
    log_->event(Record()
                    .set("event", "steady")
                    .set("ca", ca)
                    .set("D", d.D)
                    .set("L", d.L)
                    .set("residual", sol.residual)
                    .set("newton", newton)
                    .set("krylov", krylov)
                    .set("velocity_evaluations", evaluations)
                    .set("checkpoint", ckpt),
                t_);
  }

  // The state as a checkpoint of a run held at this Ca (start.from, render, figure, --resume).
  std::string write_checkpoint(double ca) {
    RunCheckpoint c;
    c.options = opt_;
    c.options.ca = control::CaSchedule{};
    control::CaSegment hold;
    hold.ca = ca;
    c.options.ca.segments.push_back(hold);
    c.options.time.t_end = std::max(opt_.time.t_end, t_ + 1.0);
    c.control = control::to_json_text(c.options);
    c.control_file = c.control;
    c.x = x_;
    c.t = t_;
    c.steps = steps_;
    c.ca = ca;
    c.schedule = control::CaScheduler(c.options.ca, c.options.steady, t_, ca).state();
    const capsule::HealthMonitor h(*mesh_, x_);
    c.health_normals = h.normals();
    c.health_flags = h.flags();
    c.wall_s = wall();
    c.note = "steady state by capflow steady";
    dir_->subdirectory("checkpoints");
    const fs::path path = dir_->checkpoint_path(++states_);
    write_run_checkpoint(c, path.string());
    return path.string();
  }

  control::ControlOptions opt_;
  std::vector<double> levels_;
  std::unique_ptr<RunDirectory> dir_;
  std::unique_ptr<RunLog> log_;
  std::unique_ptr<geometry::Mesh> mesh_;
  std::unique_ptr<capsule::Capsule> cap_;
  Eigen::Matrix3Xd x_;
  double t_ = 0;       // simulated time of all approaches
  long steps_ = 0;     // their steps
  double h_last_ = 0;  // the last adaptive step size measured
  long states_ = 0;
  std::string failure_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace

SteadySummary run_steady(const control::ControlOptions& options, bool overwrite,
                         const std::atomic<bool>* stop) {
  SteadyRun r(options, overwrite);
  return r.run(stop);
}

}  // namespace capflow::app
