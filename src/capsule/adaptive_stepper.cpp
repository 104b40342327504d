#include "capsule/adaptive_stepper.h"

#include <arkode/arkode_erkstep.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <sstream>

#include "capsule/sundials_glue.h"

namespace capflow::capsule {

namespace {

using sundials::view;
constexpr const char* kSolver = "ARKODE";

// ARKODE's explicit Gustafsson controller (arkAdaptExpGus, imethod 3, default constants AD3_K1,
// AD3_K2), its error bias (BIAS) and TINY, for the controller below; ERKStep's growth bound of a
// step over the one before (its default, set explicitly).
constexpr double kGusK1 = 0.367, kGusK2 = 0.268;
constexpr double kBias = 1.5;
constexpr double kTiny = 1e-10;
constexpr double kGrowth = 25.0;

void require(int flag, const char* call) {
  sundials::require(flag, kSolver, call);
}

}  // namespace

// The ARKODE objects and what the C callbacks report back.
struct AdaptiveStepper::Arkode {
  Rhs rhs;
  sundials::Context ctx{kSolver};
  sundials::Vector y;
  void* mem = nullptr;
  Eigen::VectorXd y_in, dydt;  // the callback's buffers
  Eigen::VectorXd y_now;       // the accepted state at time()
  std::string rhs_error;       // what the right-hand side threw
  std::string message;         // ARKODE's last error message
  long evals = 0;
  AdaptiveStepper::History history;  // the controller's memory (ours: it is saved with the state)
  double e_attempt = 1;              // the biased error estimate of the last attempt

  // ARKODE's explicit Gustafsson controller, step for step, on our own history instead of
  // ARKODE's (which a new ERKStep object - a resumed run's - does not have):
  //   the first two steps of the integrator (nst < 2, counting the attempt when it passes):
  //     h_new = h e^(-1/p);   then  h_new = h e^(-k1/p) (e / e_prev)^(-k2/p),
  // e the biased error estimate (bias dsm, at least TINY), e_prev the last accepted step's (1
  // after a restart, as ERKStepSetInitStep clears it), p the embedding's order.
  static int adapt(N_Vector, realtype, realtype h, realtype, realtype, realtype e, realtype,
                   realtype, int, int p, realtype* h_new, void* data) {
    auto* a = static_cast<Arkode*>(data);
    a->e_attempt = e;
    const long nst = a->history.steps + (e / kBias <= 1.0 ? 1 : 0);
    const double e1 = std::max(e, kTiny);
    if (nst < 2) {
      *h_new = h * std::pow(e1, -1.0 / p);
    } else {
      const double e2 = e1 / std::max(a->history.e_prev, kTiny);
      *h_new = h * std::pow(e1, -kGusK1 / p) * std::pow(e2, -kGusK2 / p);
    }
    return 0;
  }

  static int f(realtype t, N_Vector y, N_Vector ydot, void* data) {
    auto* a = static_cast<Arkode*>(data);
    try {
      a->y_in = view(y);
      a->rhs(t, a->y_in, &a->dydt);
      view(ydot) = a->dydt;
      ++a->evals;
      return 0;
    } catch (const std::exception& e) {
      a->rhs_error = e.what();
      return -1;
    }
  }
  static void on_error(int, const char*, const char* function, char* msg, void* data) {
    static_cast<Arkode*>(data)->message = std::string(function) + ": " + msg;
  }

  ~Arkode() {
    if (mem) ERKStepFree(&mem);
  }
};

namespace {

// ARKODE's message for a failed step, or the return flag's name when it reported none (it
// reports some failures, such as repeated error-test failures, only through the flag).
std::string failure_text(int flag, const std::string& message) {
  if (!message.empty()) return message;
  if (flag == ARK_ERR_FAILURE)
    return "ARK_ERR_FAILURE: the error test failed repeatedly or at the smallest step";
  std::unique_ptr<char, void (*)(void*)> name(ERKStepGetReturnFlagName(flag), std::free);
  return name ? std::string(name.get()) : "flag " + std::to_string(flag);
}

}  // namespace

AdaptiveStepper::AdaptiveStepper(Rhs rhs, const AdaptiveOptions& options)
    : ark_(std::make_unique<Arkode>()), opt_(options) {
  if (!(options.tolerance >= 1e-12 && options.tolerance <= 1e-1))
    throw std::invalid_argument("AdaptiveStepper: tolerance outside [1e-12, 0.1]");
  ark_->rhs = std::move(rhs);
}

AdaptiveStepper::~AdaptiveStepper() = default;

void AdaptiveStepper::restart(double t, const Eigen::VectorXd& y, double h) {
  begin(t, y, h);
  ark_->history.e_prev = 1.0;  // ERKStepSetInitStep clears ARKODE's error history the same way
  h_free_ = h;                 // what a restart knows of the step size
}

void AdaptiveStepper::resume(double t, const Eigen::VectorXd& y, double h, const History& hist) {
  if (!(std::isfinite(hist.e_prev) && hist.e_prev >= 0) || hist.steps < 0 ||
      !(std::isfinite(hist.h_free) && hist.h_free >= 0 && hist.h_free <= opt_.h_max))
    throw std::invalid_argument("AdaptiveStepper: invalid controller history");
  ark_->history = hist;
  begin(t, y, h);
  h_free_ = hist.h_free;
}

void AdaptiveStepper::begin(double t, const Eigen::VectorXd& y, double h) {
  Arkode& a = *ark_;
  if (!a.y.get() || a.y.size() != y.size()) {
    if (a.mem) ERKStepFree(&a.mem);
    a.y.reset(y.size(), a.ctx, kSolver);
  }
  a.y.view() = y;
  if (!a.mem) {
    a.mem = ERKStepCreate(&Arkode::f, t, a.y.get(), a.ctx.get());
    if (!a.mem) throw std::runtime_error("ARKODE: ERKStepCreate failed");
    require(ERKStepSetErrHandlerFn(a.mem, &Arkode::on_error, &a), "ERKStepSetErrHandlerFn");
    require(ERKStepSetUserData(a.mem, &a), "ERKStepSetUserData");
    require(ERKStepSetTableNum(a.mem, ARKODE_CASH_KARP_6_4_5), "ERKStepSetTableNum");
    // Gustafsson's controller for explicit methods, made for steps that are limited by
    // stability rather than accuracy (Arkode::adapt: ARKODE's, on a history we keep).
    require(ERKStepSetAdaptivityFn(a.mem, &Arkode::adapt, &a), "ERKStepSetAdaptivityFn");
    require(ERKStepSetMaxGrowth(a.mem, kGrowth), "ERKStepSetMaxGrowth");
    require(ERKStepSetMinStep(a.mem, opt_.h_min), "ERKStepSetMinStep");
    require(ERKStepSetMaxStep(a.mem, opt_.h_max), "ERKStepSetMaxStep");
    require(ERKStepSStolerances(a.mem, opt_.tolerance, opt_.tolerance), "ERKStepSStolerances");
  }
  require(ERKStepSetInitStep(a.mem, std::clamp(h, 0.0, opt_.h_max)), "ERKStepSetInitStep");
  // ARKODE bounds the growth of its first step by 1e4 and of every later one (after a reset too)
  // by kGrowth: a resumed run's new ERKStep object continues with the later bound.
  require(ERKStepSetMaxFirstGrowth(a.mem, a.history.steps > 0 ? kGrowth : 0.0),
          "ERKStepSetMaxFirstGrowth");
  require(ERKStepReset(a.mem, t, a.y.get()), "ERKStepReset");
  a.y_now = y;
  t_ = t;
  h_pending_ = h;  // next_step() until a step is taken
}

AdaptiveStepper::Step AdaptiveStepper::step(double t_stop, const Finish& finish, const Check& check,
                                            Eigen::VectorXd* y) {
  Arkode& a = *ark_;
  if (!a.mem) throw std::logic_error("AdaptiveStepper::step before restart");
  if (!(t_stop > t_)) throw std::invalid_argument("AdaptiveStepper::step: t_stop not after t");
  const double t0 = t_;
  const Eigen::VectorXd y0 = a.y_now;
  Step s;
  for (;;) {
    long fails_before = 0, fails_after = 0;
    ERKStepGetNumErrTestFails(a.mem, &fails_before);
    require(ERKStepSetStopTime(a.mem, t_stop), "ERKStepSetStopTime");
    a.rhs_error.clear();
    a.message.clear();
    const long evals_before = a.evals;
    realtype t_reached = t0;
    const int flag = ERKStepEvolve(a.mem, t_stop, a.y.get(), &t_reached, ARK_ONE_STEP);
    rhs_evals_ += a.evals - evals_before;
    ERKStepGetNumErrTestFails(a.mem, &fails_after);
    s.error_rejections += static_cast<int>(fails_after - fails_before);
    std::string why;
    bool changed = false;
    if (flag < 0) {
      why = a.rhs_error.empty() ? "the integrator failed (" + failure_text(flag, a.message) + ")"
                                : "the velocity evaluation failed: " + a.rhs_error;
    } else {
      *y = a.y.view();
      if (finish) {
        const Eigen::VectorXd before = *y;
        finish(y);
        changed = (before.array() != y->array()).any();
      }
      if (std::abs(t_reached - t_stop) <= 1e-13 * std::max(1.0, std::abs(t_stop)))
        t_reached = t_stop;
      why = check ? check(*y, t_reached) : std::string();
    }
    double h = 0;
    if (why.empty()) {
      ++a.history.steps;  // ARKODE's nst
      a.history.e_prev = a.e_attempt;  // its error history (cleared below by a restart)
      ERKStepGetLastStep(a.mem, &h);
      s.t = t_reached;
      s.h = t_reached - t0;
      t_ = t_reached;
      a.y_now = *y;
      h_pending_ = -1;
      // A step that ends on t_stop was cut short: the controller would grow the next one from
      // it and overshoot. The next step starts from the last step that was not cut (a state
      // changed by `finish` restarts as well).
      const bool cut = flag == ARK_TSTOP_RETURN;
      if (!cut) h_free_ = s.h;
      if (cut && h_free_ > 0)
        restart(t_, *y, h_free_);
      else if (changed)
        restart(t_, *y, next_step());
      return s;
    }
    ++s.check_rejections;
    if (flag < 0)
      ERKStepGetCurrentStep(a.mem, &h);
    else
      ERKStepGetLastStep(a.mem, &h);
    const double h_try = 0.25 * h;
    if (h_try < opt_.h_min || s.check_rejections > 40) {
      std::ostringstream m;
      m << why << " (the step from t = " << t0 << " was retried " << s.check_rejections
        << " times down to " << h << "; the smallest step allowed is " << opt_.h_min << ")";
      restart(t0, y0, h);
      throw StepFailure(m.str());
    }
    restart(t0, y0, h_try);
  }
}

AdaptiveStepper::History AdaptiveStepper::history() const {
  History h = ark_->history;
  h.h_free = h_free_;
  return h;
}

double AdaptiveStepper::next_step() const {
  if (h_pending_ >= 0) return h_pending_;
  double h = 0;
  if (ark_->mem) ERKStepGetCurrentStep(ark_->mem, &h);
  return h;
}

void AdaptiveStepper::set_tolerance(double tolerance) {
  if (!(tolerance >= 1e-12 && tolerance <= 1e-1))
    throw std::invalid_argument("AdaptiveStepper: tolerance outside [1e-12, 0.1]");
  opt_.tolerance = tolerance;
  if (ark_->mem)
    require(ERKStepSStolerances(ark_->mem, tolerance, tolerance), "ERKStepSStolerances");
}

}  // namespace capflow::capsule
