#include "app/time_stepper.h"

#include <algorithm>
#include <cmath>

#include "capsule/adaptive_stepper.h"
#include "capsule/chebyshev_stepper.h"
#include "control/limits.h"

namespace capflow::app {

namespace {

Eigen::Map<const Eigen::Matrix3Xd> as_positions(const Eigen::VectorXd& y) {
  return {y.data(), 3, y.size() / 3};
}

}  // namespace

TimeStepper::TimeStepper(capsule::Capsule& cap, const control::TimeOptions& time, double h_next,
                         const std::optional<History>& history)
    : cap_(cap) {
  configure(time);
  if (!stepper_) return;
  if (history && h_next > 0) {
    const Eigen::Matrix3Xd& x = cap_.positions();
    stepper_->resume(cap_.time(), Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()), h_next,
                     *history);
  } else {
    restart(h_next);
  }
}

TimeStepper::~TimeStepper() = default;

void TimeStepper::configure(const control::TimeOptions& time) {
  const bool was_adaptive = stepper_ != nullptr;
  time_ = time;
  if (!time.adaptive) {
    stepper_.reset();
    return;
  }
  if (was_adaptive) {
    stepper_->set_tolerance(time.tolerance);
    return;
  }
  capsule::AdaptiveOptions o;
  o.tolerance = time.tolerance;
  o.h_min = control::kMinTimeStep;
  o.h_max = 0.1;
  capsule::Integrator::Rhs rhs = [this](double t, const Eigen::VectorXd& y,
                                         Eigen::VectorXd* dydt) {
    const Eigen::Matrix3Xd u = cap_.velocity(as_positions(y), (*ca_)(t));
    *dydt = Eigen::Map<const Eigen::VectorXd>(u.data(), u.size());
  };
  if (time.method == control::TimeMethod::Chebyshev)
    stepper_ = std::make_unique<capsule::ChebyshevStepper>(std::move(rhs), o);
  else
    stepper_ = std::make_unique<capsule::AdaptiveStepper>(std::move(rhs), o);
  // From a fixed dt, the first adaptive step is that dt (a step known to be stable).
  if (cap_.step_count() > 0) restart(time.dt);
}

bool TimeStepper::done(double t_end) const {
  const double t = cap_.time();
  if (!time_.adaptive) return t >= t_end - 0.5 * time_.dt;
  return t >= t_end - 1e-12 * std::max(1.0, std::abs(t_end));
}

TimeStepper::History TimeStepper::history() const {
  return stepper_ ? stepper_->history() : History{};
}

double TimeStepper::next_step() const {
  return stepper_ ? stepper_->next_step() : time_.dt;
}

void TimeStepper::restart(double h) {
  if (!stepper_) return;
  const Eigen::Matrix3Xd& x = cap_.positions();
  const double h0 = h > 0 ? h : stepper_->next_step();
  stepper_->restart(cap_.time(), Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()), h0);
}

TimeStepper::Outcome TimeStepper::advance(double t_stop, const capsule::CaFunction& ca,
                                          capsule::HealthMonitor& health) {
  return stepper_ ? advance_adaptive(t_stop, ca, health) : advance_fixed(ca, health);
}

TimeStepper::Outcome TimeStepper::advance_fixed(const capsule::CaFunction& ca,
                                                capsule::HealthMonitor& health) {
  Outcome out;
  out.dt = time_.dt;
  const double t0 = cap_.time();
  const Eigen::Matrix3Xd last_good = cap_.positions();
  const long steps_prev = cap_.step_count();
  try {
    cap_.step(time_.dt, ca);
  } catch (const std::exception& e) {
    out.failure = "the step from t = " + std::to_string(t0) + " failed: " + e.what();
  }
  if (out.failure.empty()) {
    const capsule::HealthReport h = health.check(cap_.positions(), cap_.time());
    if (h.level == capsule::HealthLevel::Failure) out.failure = h.message;
    if (h.level == capsule::HealthLevel::Warning) out.warnings.push_back(h);
  }
  if (!out.failure.empty()) cap_.set_state(last_good, t0, steps_prev);
  return out;
}

TimeStepper::Outcome TimeStepper::advance_adaptive(double t_stop, const capsule::CaFunction& ca,
                                                   capsule::HealthMonitor& health) {
  Outcome out;
  ca_ = &ca;
  const auto finish = [this](Eigen::VectorXd* y) {
    Eigen::Matrix3Xd x = as_positions(*y);
    cap_.finish_step(&x);
    *y = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  };
  const auto check = [&](const Eigen::VectorXd& y, double t) -> std::string {
    const capsule::HealthReport h = health.check(as_positions(y), t);
    if (h.level == capsule::HealthLevel::Failure) return h.message;
    if (h.level == capsule::HealthLevel::Warning) out.warnings.push_back(h);
    return "";
  };
  Eigen::VectorXd y;
  try {
    const capsule::Integrator::Step s = stepper_->step(t_stop, finish, check, &y);
    cap_.accept_step(as_positions(y), s.t);
    out.dt = s.h;
    out.rejected = s.error_rejections + s.check_rejections;
  } catch (const capsule::StepFailure& e) {
    out.failure = e.what();
  }
  ca_ = nullptr;
  return out;
}

}  // namespace capflow::app
