#include "capsule/chebyshev_stepper.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace capflow::capsule {

namespace {

constexpr double kSafety = 0.8;
constexpr double kMaxGrowth = 2.0, kMaxShrink = 0.1;
constexpr double kRadiusSafety = 1.2;  // the power iteration approaches rho from below
constexpr int kRadiusIterations = 50;
constexpr double kRadiusAgreement = 0.01;

double rms(const Eigen::VectorXd& v) {
  return v.size() ? std::sqrt(v.squaredNorm() / static_cast<double>(v.size())) : 0.0;
}

// The s-stage damped Chebyshev polynomial R_s(z) = a + b T_s(w0 + w1 z): w0 = 1 + eps/s^2,
// w1 = T_s'(w0)/T_s''(w0), b = T_s''(w0)/T_s'(w0)^2, a = 1 - b T_s(w0) (rkc.f).
struct Shift {
  double w0, w1, a, b;
};

Shift chebyshev_shift(int s, double eps) {
  const double w0 = 1.0 + eps / (double(s) * s);
  double z = w0, zm = 1, dz = 1, dzm = 0, d2 = 0, d2m = 0;
  for (int j = 2; j <= s; ++j) {
    const double zj = 2 * w0 * z - zm, dzj = 2 * w0 * dz - dzm + 2 * z,
                 d2j = 2 * w0 * d2 - d2m + 4 * dz;
    zm = z, z = zj, dzm = dz, dz = dzj, d2m = d2, d2 = d2j;
  }
  const double b = d2 / (dz * dz);
  return {w0, dz / d2, 1.0 - b * z, b};
}

}  // namespace

std::complex<double> ChebyshevStepper::stability_function(int s, std::complex<double> z,
                                                          double eps) {
  const Shift c = chebyshev_shift(s, eps);
  const std::complex<double> w = c.w0 + c.w1 * z;
  std::complex<double> t0 = 1.0, t1 = w;
  for (int j = 2; j <= s; ++j) {
    const std::complex<double> t2 = 2.0 * w * t1 - t0;
    t0 = t1;
    t1 = t2;
  }
  return c.a + c.b * t1;
}

double ChebyshevStepper::real_stability_interval(int s, double eps) {
  const Shift c = chebyshev_shift(s, eps);
  return (1.0 + c.w0) / c.w1;  // where the argument w0 + w1 z of T_s reaches -1
}

int ChebyshevStepper::stages_for(double h, double rho) {
  int s = 2;
  while (s < kMaxStages && real_stability_interval(s) < h * rho) ++s;
  return s;
}

ChebyshevStepper::ChebyshevStepper(Rhs rhs, const AdaptiveOptions& options)
    : rhs_(std::move(rhs)), opt_(options) {
  set_tolerance(options.tolerance);
}

void ChebyshevStepper::set_tolerance(double tolerance) {
  if (!(tolerance >= 1e-12 && tolerance <= 1e-1))
    throw std::invalid_argument("ChebyshevStepper: tolerance outside [1e-12, 0.1]");
  opt_.tolerance = tolerance;
}

void ChebyshevStepper::f(double t, const Eigen::VectorXd& y, Eigen::VectorXd* dydt) {
  rhs_(t, y, dydt);
  ++evals_;
  if (!dydt->allFinite()) throw std::runtime_error("the velocity is not finite");
}

void ChebyshevStepper::restart(double t, const Eigen::VectorXd& y, double h) {
  resume(t, y, std::clamp(h, 0.0, opt_.h_max), History{0.0, hist_.steps, 0.0, 0.0});
}

void ChebyshevStepper::resume(double t, const Eigen::VectorXd& y, double h, const History& hist) {
  if (!(std::isfinite(hist.e_prev) && hist.e_prev >= 0) || hist.steps < 0 ||
      !(std::isfinite(hist.h_free) && hist.h_free >= 0 && hist.h_free <= opt_.h_max) ||
      !(std::isfinite(hist.rho) && hist.rho >= 0) || !(std::isfinite(h) && h >= 0))
    throw std::invalid_argument("ChebyshevStepper: invalid controller history");
  t_ = t;
  y_ = y;
  f_valid_ = false;
  h_next_ = h;
  hist_ = hist;
}

double ChebyshevStepper::estimate_radius() {
  // rkc.f's RKCRHO: v is kept at a fixed small distance from y along the dominant direction of
  // df/dy, v <- y + dy (f(v) - f(y)) / |f(v) - f(y)|; sigma = |f(v) - f(y)| / dy -> rho.
  const double eps = std::sqrt(std::numeric_limits<double>::epsilon());
  const double ynorm = y_.norm();
  const double dy = ynorm > 0 ? ynorm * eps : eps;
  // Start from node-to-node alternation, which the stiffest (shortest) modes dominate: f(y)
  // itself is dominated by the smooth modes, and the iteration can stall on one of them.
  Eigen::VectorXd dir(y_.size());
  for (Eigen::Index i = 0; i < dir.size(); ++i) dir(i) = ((i / 3) % 2) ? 1.0 : -1.0;
  Eigen::VectorXd v = y_ + (dy / dir.norm()) * dir;
  Eigen::VectorXd fv;
  double sigma = 0, last = 0;
  int agreed = 0;
  for (int k = 0; k < kRadiusIterations; ++k) {
    f(t_, v, &fv);
    fv -= f_;
    const double df = fv.norm();
    if (!(df > 0)) break;  // f is constant along v: keep the last sigma
    last = sigma;
    sigma = df / dy;
    agreed = (k > 0 && std::abs(sigma - last) <= kRadiusAgreement * sigma) ? agreed + 1 : 0;
    if (agreed == 2) break;
    v = y_ + (dy / df) * fv;
  }
  return kRadiusSafety * std::max(sigma, last);
}

void ChebyshevStepper::rkc(double h, int s, Eigen::VectorXd* y1) {
  // rkc.f's STEP, with the Chebyshev polynomials T_j(w0) and their first two derivatives
  // evaluated by their recurrences (Verwer, Hundsdorfer & Sommeijer 1990).
  const Shift c = chebyshev_shift(s, kDamping);
  const double w0 = c.w0, w1 = c.w1;
  double bjm1 = 1.0 / ((2.0 * w0) * (2.0 * w0)), bjm2 = bjm1;
  yjm2_ = y_;
  double mus = w1 * bjm1;
  yjm1_ = y_ + (h * mus) * f_;
  double thjm2 = 0, thjm1 = mus;
  double zjm1 = w0, zjm2 = 1, dzjm1 = 1, dzjm2 = 0, d2zjm1 = 0, d2zjm2 = 0;
  for (int j = 2; j <= s; ++j) {
    const double zj = 2 * w0 * zjm1 - zjm2;
    const double dzj = 2 * w0 * dzjm1 - dzjm2 + 2 * zjm1;
    const double d2zj = 2 * w0 * d2zjm1 - d2zjm2 + 4 * dzjm1;
    const double bj = d2zj / (dzj * dzj);
    const double ajm1 = 1 - zjm1 * bjm1;
    const double mu = 2 * w0 * bj / bjm1, nu = -bj / bjm2;
    mus = mu * w1 / w0;
    f(t_ + h * thjm1, yjm1_, &work_);
    work_ = mu * yjm1_ + nu * yjm2_ + (1 - mu - nu) * y_ + (h * mus) * (work_ - ajm1 * f_);
    const double thj = mu * thjm1 + nu * thjm2 + mus * (1 - ajm1);
    std::swap(yjm2_, yjm1_);
    std::swap(yjm1_, work_);  // yjm1_ = Y_j, yjm2_ = Y_{j-1}
    thjm2 = thjm1;
    thjm1 = thj;
    bjm2 = bjm1;
    bjm1 = bj;
    zjm2 = zjm1;
    zjm1 = zj;
    dzjm2 = dzjm1;
    dzjm1 = dzj;
    d2zjm2 = d2zjm1;
    d2zjm1 = d2zj;
  }
  *y1 = yjm1_;
}

double ChebyshevStepper::error_norm(double h, const Eigen::VectorXd& y1,
                                    const Eigen::VectorXd& f1) const {
  // rkc.f: est = 0.8 (y_n - y_n+1) + 0.4 h (f_n + f_n+1), an estimate of the local error of the
  // second-order step, weighted by atol + rtol max(|y_n|, |y_n+1|) (atol = rtol = tolerance).
  const double tol = opt_.tolerance;
  const Eigen::ArrayXd est = 0.8 * (y_ - y1).array() + (0.4 * h) * (f_ + f1).array();
  const Eigen::ArrayXd wt = tol + tol * y_.array().abs().max(y1.array().abs());
  return rms((est / wt).matrix());
}

ChebyshevStepper::Step ChebyshevStepper::step(double t_stop, const Finish& finish,
                                              const Check& check, Eigen::VectorXd* y) {
  if (y_.size() == 0) throw std::logic_error("ChebyshevStepper::step before restart");
  if (!(t_stop > t_)) throw std::invalid_argument("ChebyshevStepper::step: t_stop not after t");
  const double t0 = t_;
  Step s;
  bool fresh_radius = false;  // estimated during this step
  std::string why;
  Eigen::VectorXd y1, f1;
  double h = 0;
  for (;;) {
    try {
      if (!f_valid_) {
        f(t_, y_, &f_);
        f_valid_ = true;
      }
      if (!fresh_radius && (hist_.rho <= 0 || hist_.steps % kRadiusSteps == 0 ||
                            s.error_rejections > 0)) {
        hist_.rho = estimate_radius();
        fresh_radius = true;
      }
      h = h_next_;
      if (!(h > 0)) {  // rkc.f's initial step: 0.1 / sqrt(|f'| / weight) within 1 / rho
        h = std::min(opt_.h_max, hist_.rho > 0 ? 1.0 / hist_.rho : opt_.h_max);
        f(t_, y_ + h * f_, &work_);
        const Eigen::ArrayXd wt = opt_.tolerance * (1.0 + y_.array().abs());
        const double est = h * rms(((work_ - f_).array() / wt).matrix());
        h = 0.1 * h < opt_.h_max * std::sqrt(est) ? std::max(0.1 * h / std::sqrt(est), opt_.h_min)
                                                   : opt_.h_max;
      }
      h = std::min(h, opt_.h_max);
      bool cut = false;
      if (t_ + h >= t_stop - 1e-13 * std::max(1.0, std::abs(t_stop))) {
        h = t_stop - t_;
        cut = true;
      }
      const int stages = stages_for(h, hist_.rho);
      if (real_stability_interval(stages) < h * hist_.rho) {  // more than kMaxStages needed
        h = real_stability_interval(stages) / hist_.rho;
        cut = false;
      }
      if (h < opt_.h_min) {
        std::ostringstream m;
        m << (why.empty() ? "the error test failed" : why) << " (the step from t = " << t0
          << " fell to " << h << "; the smallest step allowed is " << opt_.h_min << ")";
        throw StepFailure(m.str());
      }
      last_stages_ = stages;
      rkc(h, stages, &y1);
      f(t_ + h, y1, &f1);
      const double err = error_norm(h, y1, f1);
      if (!(err <= 1.0)) {
        ++s.error_rejections;
        why = "the error test failed";
        h_next_ = h * std::max(kMaxShrink, std::isfinite(err) ? kSafety / std::cbrt(err) : 0.0);
        continue;
      }
      *y = y1;
      bool changed = false;
      if (finish) {
        finish(y);
        changed = (y->array() != y1.array()).any();
      }
      const double t1 = cut ? t_stop : t_ + h;
      why = check ? check(*y, t1) : std::string();
      if (!why.empty()) {
        ++s.check_rejections;
        if (s.check_rejections > 40) throw StepFailure(why + " (the step from t = " +
                                                       std::to_string(t0) + " was retried 40 times)");
        h_next_ = 0.25 * h;
        continue;
      }
      // rkc.f's controller: the first step after a restart from this error alone, later ones
      // with the predictive (Gustafsson) formula from the last accepted step's error.
      const double e = std::max(err, 1e-10);
      double fac = kMaxGrowth;
      if (hist_.e_prev <= 0 || hist_.h_free <= 0)
        fac = std::min(fac, kSafety / std::cbrt(e));
      else
        fac = std::min(fac, kSafety * (h / hist_.h_free) * std::cbrt(hist_.e_prev) /
                                std::pow(e, 2.0 / 3.0));
      double h_new = std::max(kMaxShrink, fac) * h;
      if (cut) h_new = std::max(h_new, hist_.h_free);  // a step cut at t_stop is not a measure
      h_next_ = std::min(h_new, opt_.h_max);
      if (!cut) {
        hist_.e_prev = err;
        hist_.h_free = h;
      }
      ++hist_.steps;
      t_ = t1;
      std::swap(y_, *y);
      *y = y_;
      if (changed) {
        f_valid_ = false;
      } else {
        std::swap(f_, f1);
      }
      s.t = t_;
      s.h = t_ - t0;
      return s;
    } catch (const StepFailure&) {
      throw;
    } catch (const std::exception& e) {
      ++s.check_rejections;
      why = std::string("the velocity evaluation failed: ") + e.what();
      if (!f_valid_ || s.check_rejections > 40)
        throw StepFailure(why + " (at t = " + std::to_string(t0) + ")");
      h_next_ = 0.25 * (h > 0 ? h : opt_.h_max);
      fresh_radius = true;  // do not estimate again from a state whose f fails
    }
  }
}

}  // namespace capflow::capsule
