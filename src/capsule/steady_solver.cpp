#include "capsule/steady_solver.h"

#include <kinsol/kinsol.h>
#include <kinsol/kinsol_ls.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "capsule/sundials_glue.h"

namespace capflow::capsule {

namespace {

using sundials::view;
constexpr const char* kSolver = "KINSOL";

// The fixed-point residual of the midpoint step map on the reduced node set.
class StepMap {
 public:
  StepMap(const Capsule& cap, double h) : cap_(cap), h_(h) {}

  Eigen::Matrix3Xd expand(const Eigen::VectorXd& y) const {
    const Eigen::Map<const Eigen::Matrix3Xd> at(y.data(), 3, y.size() / 3);
    Eigen::Matrix3Xd x;
    cap_.symmetry().expand(at, &x);
    return x;
  }
  Eigen::VectorXd reduce(const Eigen::Matrix3Xd& x) const {
    const std::vector<int>& t = cap_.symmetry().targets();
    Eigen::VectorXd y(3 * t.size());
    for (size_t k = 0; k < t.size(); ++k) y.segment<3>(3 * k) = x.col(t[k]);
    return y;
  }
  // F(y) = (P(Phi_h(E y)) - E y)|targets / h.
  Eigen::VectorXd residual(const Eigen::VectorXd& y, double ca) const {
    if (!(ca > 0)) throw std::domain_error("Ca <= 0 in the Newton iteration");
    Eigen::Matrix3Xd x1 = cap_.midpoint_step(expand(y), h_, ca);
    x1 = rescale_to_volume(cap_.mesh(), x1, cap_.initial_volume());
    return (reduce(x1) - y) / h_;
  }

 private:
  const Capsule& cap_;
  double h_;
};

// The unknowns and equations KINSOL sees: the reduced positions y at a fixed Ca, or (y, Ca) with
// the hyperplane <tangent, (E y, Ca) - predicted> = 0 (continuation.h's inner product) appended.
class System {
 public:
  System(const StepMap& map, double ca) : map_(map), ca_(ca) {}
  System(const StepMap& map, const BranchPoint& predicted, const BranchPoint& normal)
      : map_(map), ca_(predicted.ca), hyperplane_(true), predicted_(predicted), normal_(normal) {}

  Eigen::VectorXd start(const Eigen::Matrix3Xd& x0) const {
    const Eigen::VectorXd y = map_.reduce(x0);
    if (!hyperplane_) return y;
    Eigen::VectorXd z(y.size() + 1);
    z << y, ca_;
    return z;
  }
  Eigen::VectorXd shape(const Eigen::VectorXd& z) const {
    return hyperplane_ ? Eigen::VectorXd(z.head(z.size() - 1)) : z;
  }
  double ca(const Eigen::VectorXd& z) const { return hyperplane_ ? z(z.size() - 1) : ca_; }
  Eigen::VectorXd residual(const Eigen::VectorXd& z) const {
    const Eigen::VectorXd y = shape(z);
    const Eigen::VectorXd f = map_.residual(y, ca(z));
    if (!hyperplane_) return f;
    const Eigen::Matrix3Xd x = map_.expand(y);
    BranchPoint p{Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()), ca(z)};
    Eigen::VectorXd out(f.size() + 1);
    out << f, branch_dot(normal_, branch_difference(p, predicted_));
    return out;
  }

 private:
  const StepMap& map_;
  double ca_;
  bool hyperplane_ = false;
  BranchPoint predicted_, normal_;
};

struct Kinsol {
  sundials::Context ctx{kSolver};
  sundials::Vector y, scale;
  std::unique_ptr<sundials::Spgmr> ls;
  void* mem = nullptr;
  const System* system = nullptr;
  const std::atomic<bool>* stop = nullptr;
  std::string error, message;

  static int f(N_Vector y, N_Vector fy, void* data) {
    auto* k = static_cast<Kinsol*>(data);
    if (k->stop && k->stop->load()) {
      k->error = "stopped";
      return -1;  // unrecoverable: KINSol returns
    }
    try {
      view(fy) = k->system->residual(view(y));
      return view(fy).allFinite() ? 0 : 1;
    } catch (const std::exception& e) {
      k->error = e.what();
      return 1;  // recoverable: KINSOL's line search backs off
    }
  }
  static void on_error(int, const char*, const char*, char* msg, void* data) {
    static_cast<Kinsol*>(data)->message = msg;
  }
  ~Kinsol() {
    if (mem) KINFree(&mem);
  }
};

void require(int flag, const char* call) {
  sundials::require(flag, kSolver, call);
}

// KINSOL's own sentence for its return flag.
std::string describe(int flag) {
  switch (flag) {
    case KIN_SUCCESS:
      return "converged";
    case KIN_INITIAL_GUESS_OK:
      return "the initial state is already a root";
    case KIN_STEP_LT_STPTOL:
      return "the Newton steps became negligible before the residual met the tolerance";
    case KIN_LINESEARCH_NONCONV:
      return "the line search found no decrease of the residual";
    case KIN_MAXITER_REACHED:
      return "the Newton iterations reached their limit";
    case KIN_MXNEWT_5X_EXCEEDED:
      return "five Newton steps in a row were too long";
    case KIN_LINSOLV_NO_RECOVERY:
    case KIN_LINIT_FAIL:
    case KIN_LSOLVE_FAIL:
      return "GMRES failed";
    case KIN_SYSFUNC_FAIL:
    case KIN_REPTD_SYSFUNC_ERR:
    case KIN_FIRST_SYSFUNC_ERR:
      return "the velocity evaluation failed";
    default:
      return "KINSOL stopped (flag " + std::to_string(flag) + ")";
  }
}

}  // namespace

bool is_pure_straining(const Eigen::Matrix3d& g) {
  const double big = g.cwiseAbs().maxCoeff();
  return big > 0 && (g - g.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * big;
}

namespace {

SteadySolution solve(const Capsule& cap, const StepMap& map, const System& system,
                     const Eigen::Matrix3Xd& x0, const SteadySolveOptions& o) {
  if (!(o.step > 0)) throw std::invalid_argument("solve_steady: step must be > 0");
  const long evals_before = cap.velocity_evaluations();
  const Eigen::VectorXd z0 = system.start(x0);

  Kinsol k;
  k.system = &system;
  k.stop = o.stop;
  k.y.reset(z0.size(), k.ctx, kSolver);
  k.scale.reset(z0.size(), k.ctx, kSolver);
  k.y.view() = z0;
  k.scale.view().setOnes();
  k.mem = KINCreate(k.ctx.get());
  if (!k.mem) throw std::runtime_error("KINSOL: KINCreate failed");
  require(KINInit(k.mem, &Kinsol::f, k.y.get()), "KINInit");
  require(KINSetUserData(k.mem, &k), "KINSetUserData");
  require(KINSetErrHandlerFn(k.mem, &Kinsol::on_error, &k), "KINSetErrHandlerFn");
  require(KINSetPrintLevel(k.mem, 0), "KINSetPrintLevel");
  require(KINSetFuncNormTol(k.mem, o.tolerance), "KINSetFuncNormTol");
  require(KINSetScaledStepTol(k.mem, 1e-14), "KINSetScaledStepTol");
  require(KINSetNumMaxIters(k.mem, o.max_newton), "KINSetNumMaxIters");
  require(KINSetMaxSetupCalls(k.mem, 1), "KINSetMaxSetupCalls");
  k.ls = std::make_unique<sundials::Spgmr>(k.y, o.max_krylov, 1, k.ctx, kSolver);
  require(KINSetLinearSolver(k.mem, k.ls->get(), nullptr), "KINSetLinearSolver");

  const int flag = KINSol(k.mem, k.y.get(), KIN_LINESEARCH, k.scale.get(), k.scale.get());
  SteadySolution s;
  long nni = 0, nli = 0;
  KINGetNumNonlinSolvIters(k.mem, &nni);
  KINGetNumLinIters(k.mem, &nli);
  s.newton = static_cast<int>(nni);
  s.krylov = nli;
  const Eigen::VectorXd z = k.y.view();
  s.ca = system.ca(z);
  s.x = map.expand(system.shape(z));
  if (s.ca > 0) {
    s.residual = system.residual(z).cwiseAbs().maxCoeff();
    s.speed = cap.velocity(s.x, s.ca).cwiseAbs().maxCoeff();
  } else {
    s.residual = s.speed = std::numeric_limits<double>::infinity();
  }
  s.converged = (flag == KIN_SUCCESS || flag == KIN_INITIAL_GUESS_OK) && s.residual <= o.tolerance;
  s.message = describe(flag);
  if (!k.error.empty()) s.message += " (" + k.error + ")";
  s.evaluations = cap.velocity_evaluations() - evals_before;
  return s;
}

}  // namespace

SteadySolution solve_steady(const Capsule& cap, const Eigen::Matrix3Xd& x0, double ca,
                            const SteadySolveOptions& o) {
  if (!(ca > 0)) throw std::invalid_argument("solve_steady: Ca must be > 0");
  const StepMap map(cap, o.step);
  return solve(cap, map, System(map, ca), x0, o);
}

SteadySolution solve_steady_on_hyperplane(const Capsule& cap, const BranchPoint& predicted,
                                          const BranchPoint& normal, const SteadySolveOptions& o) {
  if (!(predicted.ca > 0)) throw std::invalid_argument("solve_steady: Ca must be > 0");
  const StepMap map(cap, o.step);
  const Eigen::Map<const Eigen::Matrix3Xd> x0(predicted.y.data(), 3, predicted.y.size() / 3);
  return solve(cap, map, System(map, predicted, normal), x0, o);
}

}  // namespace capflow::capsule
