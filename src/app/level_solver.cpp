// capflow/app/level_solver: see level_solver.h.
#include "app/level_solver.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "app/format.h"
#include "app/time_stepper.h"
#include "app/worker_team.h"
#include "capsule/health.h"
#include "control/control_file.h"
#include "geometry/surface.h"

namespace capflow::app {

namespace {

std::string scientific(double v) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(2) << v;
  return s.str();
}

Eigen::VectorXd flat(const Eigen::Matrix3Xd& x) {
  return Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
}

Eigen::Matrix3Xd positions(const capsule::BranchPoint& p) {
  return Eigen::Map<const Eigen::Matrix3Xd>(p.y.data(), 3, p.y.size() / 3);
}

// The largest angle between the unit normals of neighbouring nodes of grid g's state: above
// the health check's resolution limit the grid does not resolve the tips.
double normal_turning(const Grid& g) {
  return geometry::max_normal_turning(*g.mesh, geometry::compute_geometry(*g.mesh, g.x).n);
}

bool resolves_tips(double turning) {
  return turning <= capsule::HealthOptions{}.resolution_warn_angle;
}

}  // namespace

Grid make_grid(const control::ControlOptions& o) {
  Grid g;
  g.mesh = control::make_mesh(o.mesh);
  g.cap = std::make_unique<capsule::Capsule>(*g.mesh, o.law, o.flow, control::dynamics_options(o));
  attach_team(*g.cap, o);  // the ranks of an MPI run share its velocity evaluations
  g.x = g.cap->positions();
  return g;
}

Eigen::Matrix3Xd resampled(const geometry::Mesh& from, const Eigen::Matrix3Xd& x, const Grid& g) {
  const Eigen::Matrix3Xd y = geometry::resample_surface(from, x, *g.mesh);
  return y.allFinite() ? capsule::rescale_to_volume(*g.mesh, y, g.cap->initial_volume()) : y;
}

double oscillation(const Grid& g) {
  return capsule::HealthMonitor(*g.mesh, g.x).oscillation_indicator(g.x);
}

LevelSolver::LevelSolver(const control::ControlOptions& options, Grid& fine, Hooks hooks)
    : opt_(options), fine_(fine), hooks_(std::move(hooks)) {}

// Adaptive time steps on grid g at Ca = ca from g.x until the node speed is below `speed`.
// Returns the median of the last accepted steps (0 when none), or -1 when the march failed.
double LevelSolver::approach(Grid& g, double ca, double speed) {
  control::TimeOptions time = opt_.time;
  time.adaptive = true;
  // The explicit pair's steps settle at the stability limit, which sizes the midpoint map
  // (kMapStepFactor); Runge-Kutta-Chebyshev steps are longer and say nothing about it.
  time.method = control::TimeMethod::CashKarp;
  g.cap->set_state(g.x, t_, steps_);
  TimeStepper st(*g.cap, time, g.h_last);
  capsule::HealthMonitor health(*g.mesh, g.x);
  const capsule::CaFunction level = [ca](double) { return ca; };
  const double t0 = t_;
  std::vector<double> steps;
  double v = std::numeric_limits<double>::infinity();
  while (v > speed || steps.size() < kMinApproachSteps) {
    if (hooks_.between_steps) hooks_.between_steps();
    if (stopped() || t_ - t0 > kMaxApproachTime) break;
    const Eigen::Matrix3Xd before = g.cap->positions();
    const TimeStepper::Outcome o = st.advance(t_ + 1.0, level, health);
    if (!o.failure.empty()) {
      failure_ = o.failure;
      return -1;  // g.x: the state the approach started from
    }
    t_ = g.cap->time();
    ++steps_;
    v = (g.cap->positions() - before).cwiseAbs().maxCoeff() / o.dt;
    steps.push_back(o.dt);
    if (hooks_.status) {
      std::ostringstream m;
      m << "Ca=" << ca << " approach: t=" << fixed(t_ - t0, 3) << " node speed "
        << std::scientific << std::setprecision(2) << v << " (until " << speed << "), dt "
        << o.dt;
      hooks_.status(m.str());
    }
  }
  g.x = g.cap->positions();
  if (steps.empty()) return g.h_last;
  const size_t n = std::min<size_t>(steps.size(), 10);
  std::vector<double> last(steps.end() - n, steps.end());
  std::sort(last.begin(), last.end());
  g.h_last = last[n / 2];
  return g.h_last;
}

// Approach and Newton on grid g, up to kSolveAttempts times. False when stopped or when the
// approach failed (failure_ says why); otherwise *sol is the last solve (failure_ says why
// when it did not converge).
bool LevelSolver::solve_on(Grid& g, double ca, capsule::SteadySolution* sol, int* newton,
                           long* krylov) {
  double speed = kApproachSpeed;
  for (int attempt = 0; attempt < kSolveAttempts; ++attempt, speed /= 4) {
    const double h = approach(g, ca, speed);
    if (&g == &fine_ && h > 0) h_ca_ = ca;
    if (h < 0) {
      failure_ = "the approach failed: " + failure_;
      approach_failed_ = true;
      return false;
    }
    if (stopped()) return false;
    capsule::SteadySolveOptions so;
    so.step = kMapStepFactor * h;
    so.tolerance = opt_.steady.solve_tolerance;
    so.stop = hooks_.stop;
    *sol = capsule::solve_steady(*g.cap, g.x, ca, so);
    *newton += sol->newton;
    *krylov += sol->krylov;
    std::ostringstream m;
    m << "Ca = " << ca << " (NB=" << g.mesh->nb() << "): Newton "
      << (sol->converged ? "converged" : "did not converge") << " (" << sol->message << ") in "
      << sol->newton << " iterations, " << sol->krylov << " GMRES iterations, residual "
      << std::scientific << std::setprecision(2) << sol->residual << " (map step " << so.step
      << ", approach to t = " << std::defaultfloat << t_ << ")";
    say(m.str());
    if (sol->converged) {
      g.x = sol->x;
      return true;
    }
    if (stopped()) return false;
  }
  failure_ = "no steady state found: " + sol->message + ", residual " + scientific(sol->residual);
  return true;
}

Grid LevelSolver::coarse_grid() const {
  control::ControlOptions co = opt_;
  co.mesh.nb = kCoarseNb;
  return make_grid(co);
}

// The first level from rest on a fine grid: solved on NB=8 first (cheap evaluations for the
// long approach from the sphere) and resampled onto the fine grid as its starting state.
// Returns whether that NB=8 state resolves its tips (false when there is none).
bool LevelSolver::coarse_start(double ca, int* newton, long* krylov, long* evaluations) {
  Grid coarse = coarse_grid();
  capsule::SteadySolution sol;
  const bool ran = solve_on(coarse, ca, &sol, newton, krylov);
  *evaluations += coarse.cap->velocity_evaluations();
  if (!ran || !sol.converged) {
    if (!stopped())
      say("the NB=" + std::to_string(kCoarseNb) + " start found no steady state (" + failure_ +
          "): from rest on NB=" + std::to_string(opt_.mesh.nb));
    failure_.clear();
    return false;
  }
  fine_.x = resampled(*coarse.mesh, coarse.x, fine_);
  say("Ca = " + fixed(ca, 6) + ": the NB=" + std::to_string(kCoarseNb) +
      " steady state resampled onto NB=" + std::to_string(opt_.mesh.nb));
  return resolves_tips(normal_turning(coarse));
}

// The smallest principal tension of the fine grid's state.
double LevelSolver::tau_min() const {
  return fine_.cap->fields(fine_.x).tension2.minCoeff();
}

// The first level again, along the branch from a start that resolves its tips (see the
// header). False when stopped, when no start resolves its tips or when the branch does not
// reach ca (failure_ says why); fine_.x and *sol are then unchanged.
bool LevelSolver::climb(double ca, capsule::SteadySolution* sol, int* newton, long* krylov,
                        long* evaluations) {
  const Eigen::Matrix3Xd kept = fine_.x;
  const double kept_h = fine_.h_last, kept_h_ca = h_ca_;
  const auto give_up = [&](const std::string& why) {
    failure_ = why;
    fine_.x = kept;
    fine_.h_last = kept_h;
    h_ca_ = kept_h_ca;
    return false;
  };
  Grid coarse = coarse_grid();
  double low = ca;
  bool found = false;
  for (int k = 0; k < kClimbTries && !found && !stopped(); ++k) {
    low *= kClimbFactor;
    capsule::SteadySolution s;
    if (!solve_on(coarse, low, &s, newton, krylov) || !s.converged) {
      if (!stopped())
        say("climb: no NB=" + std::to_string(kCoarseNb) + " state at Ca = " + fixed(low, 6) +
            " (" + failure_ + ")");
      continue;  // the march's or Newton's failure there: lower Ca again
    }
    const double turning = normal_turning(coarse);
    found = resolves_tips(turning);
    say("climb: the NB=" + std::to_string(kCoarseNb) + " state at Ca = " + fixed(low, 6) +
        (found ? " resolves its tips" : " does not resolve its tips") + " (the normal turns by " +
        fixed(turning, 2) + " rad between neighbouring nodes)");
  }
  *evaluations += coarse.cap->velocity_evaluations();
  if (stopped()) return give_up("stopped");
  if (!found)
    return give_up("no NB=" + std::to_string(kCoarseNb) + " state down to Ca = " + fixed(low, 6) +
                   " resolves its tips");
  if (hooks_.event) hooks_.event(control::Record().set("event", "climb").set("ca", ca)
                                     .set("from_ca", low));
  fine_.x = resampled(*coarse.mesh, coarse.x, fine_);
  capsule::SteadySolution s;
  if (!solve_on(fine_, low, &s, newton, krylov) || !s.converged)
    return give_up("Ca = " + fixed(low, 6) + ": " + failure_);
  capsule::ContinuationOptions co;
  co.from = low;
  co.to = ca;
  co.step = (ca - low) / kClimbStates;
  co.after_fold = 0;
  capsule::ArclengthContinuation branch(co, capsule::BranchPoint{flat(fine_.x), low});
  Corrections k;
  for (;;) {
    const capsule::ArclengthContinuation::Status status =
        branch.advance([&](const capsule::BranchPoint& p, const capsule::BranchPoint& n,
                           int* it) { return correct(p, n, &k, it); });
    *newton += k.newton;
    *krylov += k.krylov;
    k.newton = 0;
    k.krylov = 0;
    if (stopped()) return give_up("stopped");
    if (status == capsule::ArclengthContinuation::Status::Stuck)
      return give_up("the branch from Ca = " + fixed(low, 6) + " ends: " + branch.why());
    if (status == capsule::ArclengthContinuation::Status::Done) break;
    fine_.x = positions(branch.last());
  }
  if (std::abs(branch.last().ca - ca) > 1e-9 * ca)
    return give_up("the branch from Ca = " + fixed(low, 6) + " turns back at Ca = " +
                   fixed(branch.fold() ? branch.fold()->ca : branch.last().ca, 6) +
                   " before reaching " + fixed(ca, 6));
  if (const double a = oscillation(fine_); a > capsule::HealthOptions{}.oscillation_fail)
    return give_up("the branch reaches Ca = " + fixed(ca, 6) +
                   " with node-to-node oscillation (highest-mode amplitude " + scientific(a) +
                   " of the element size, above the time steps' limit " +
                   scientific(capsule::HealthOptions{}.oscillation_fail) +
                   "): NB=" + std::to_string(opt_.mesh.nb) +
                   " does not resolve the state there (raise mesh.nb)");
  *sol = k.last;
  return true;
}

LevelSolver::Result LevelSolver::solve(double ca, bool from_rest) {
  Result r;
  const long evals0 = fine_.cap->velocity_evaluations();
  approach_failed_ = false;  // this level's
  failure_.clear();
  bool resolved_start = true;
  if (from_rest && opt_.mesh.nb > kCoarseNb)
    resolved_start = coarse_start(ca, &r.newton, &r.krylov, &r.evaluations);
  if (stopped()) return r;
  bool ran = solve_on(fine_, ca, &r.solution, &r.newton, &r.krylov);
  if (stopped()) return r;
  if (!resolved_start) {
    // Where the NB=8 start does not resolve the tips (or found no state): no root, or a root
    // with compressive tension, is solved again along the branch from a lower Ca (climb).
    const bool found = ran && r.solution.converged;
    std::ostringstream m;
    if (!found)
      m << "Ca = " << ca << ": no steady state on NB=" << opt_.mesh.nb << " (" << failure_ << ")";
    else if (const double tau = tau_min(); tau < 0)
      m << "Ca = " << ca << ": the root on NB=" << opt_.mesh.nb
        << " has compressive tension (tau_min = " << tau << ")";
    if (!m.str().empty()) {
      say(m.str() + ", and the NB=" + std::to_string(kCoarseNb) +
          " start does not resolve the tips: solved again along the branch from a lower Ca");
      const std::string first_failure = failure_;
      const bool first_approach_failed = approach_failed_;
      if (climb(ca, &r.solution, &r.newton, &r.krylov, &r.evaluations)) {
        ran = true;
        approach_failed_ = false;
        failure_.clear();
      } else {
        if (stopped()) return r;
        say("climb: " + failure_ + (found ? "; the first root stands" : ""));
        failure_ = found ? first_failure : first_failure + "; climb: " + failure_;
        approach_failed_ = first_approach_failed;
      }
    }
  }
  r.evaluations += fine_.cap->velocity_evaluations() - evals0;
  r.converged = ran && r.solution.converged;
  r.approach_failed = approach_failed_;
  r.failure = failure_;
  return r;
}

std::optional<capsule::BranchPoint> LevelSolver::correct(const capsule::BranchPoint& p,
                                                         const capsule::BranchPoint& normal,
                                                         Corrections* k, int* newton) {
  if (std::abs(p.ca - h_ca_) > 0.2 * h_ca_) measure_step(p.ca);
  capsule::SteadySolveOptions so;
  so.step = kMapStepFactor * fine_.h_last;
  so.tolerance = opt_.steady.solve_tolerance;
  so.stop = hooks_.stop;
  k->last = capsule::solve_steady_on_hyperplane(*fine_.cap, p, normal, so);
  k->newton += k->last.newton;
  k->krylov += k->last.krylov;
  *newton = k->last.newton;
  std::ostringstream m;
  m << "branch: predicted Ca = " << p.ca << ", Newton "
    << (k->last.converged ? "converged" : "did not converge") << " at Ca = " << k->last.ca << " ("
    << k->last.message << ") in " << k->last.newton << " iterations, " << k->last.krylov
    << " GMRES iterations, residual " << std::scientific << std::setprecision(2)
    << k->last.residual;
  say(m.str());
  if (!k->last.converged) return std::nullopt;
  return capsule::BranchPoint{flat(k->last.x), k->last.ca};
}

// The stability limit at Ca: kMinApproachSteps adaptive steps from the last state (which is
// kept, as is the simulated time).
void LevelSolver::measure_step(double ca) {
  const Eigen::Matrix3Xd x = fine_.x;
  const double t = t_, h = fine_.h_last;
  if (approach(fine_, ca, std::numeric_limits<double>::infinity()) < 0)
    fine_.h_last = h;  // the march failed: keep the last measurement
  else
    h_ca_ = ca;
  fine_.x = x;
  t_ = t;
}

}  // namespace capflow::app
