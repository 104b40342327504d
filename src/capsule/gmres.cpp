#include "capsule/gmres.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sunlinsol/sunlinsol_spgmr.h>

#include <exception>
#include <stdexcept>
#include <string>

namespace capflow::capsule {

namespace {
Eigen::Map<Eigen::VectorXd> view(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(N_VGetLength(v))};
}
void require(int flag, const char* call) {
  if (flag != 0)
    throw std::runtime_error(std::string("GMRES: ") + call + " failed (flag " +
                             std::to_string(flag) + ")");
}
}  // namespace

struct Gmres::Impl {
  int n = 0;
  GmresOptions opt;
  SUNContext ctx = nullptr;
  N_Vector x = nullptr, b = nullptr;
  SUNLinearSolver ls = nullptr;
  const Operator* op = nullptr;
  std::exception_ptr error;  // an exception of the operator, rethrown after SPGMR returns
  Eigen::VectorXd v, out;

  static int atimes(void* data, N_Vector v, N_Vector z) {
    auto* m = static_cast<Impl*>(data);
    try {
      m->v = view(v);
      (*m->op)(m->v, m->out);
      if (m->out.size() != m->n) throw std::logic_error("GMRES: the operator changed the size");
      view(z) = m->out;
      return 0;
    } catch (...) {
      m->error = std::current_exception();
      return -1;  // unrecoverable: SPGMR returns
    }
  }
  ~Impl() {
    if (ls) SUNLinSolFree(ls);
    if (x) N_VDestroy(x);
    if (b) N_VDestroy(b);
    if (ctx) SUNContext_Free(&ctx);
  }
};

Gmres::Gmres(int n, GmresOptions options) : impl_(std::make_unique<Impl>()) {
  if (n < 1) throw std::invalid_argument("GMRES: the system needs at least one unknown");
  if (options.max_krylov < 1 || options.max_restarts < 0 || !(options.tolerance > 0))
    throw std::invalid_argument("GMRES: need max_krylov >= 1, max_restarts >= 0, tolerance > 0");
  Impl& m = *impl_;
  m.n = n;
  m.opt = options;
  require(SUNContext_Create(nullptr, &m.ctx), "SUNContext_Create");
  m.x = N_VNew_Serial(n, m.ctx);
  m.b = N_VNew_Serial(n, m.ctx);
  if (!m.x || !m.b) throw std::runtime_error("GMRES: N_VNew_Serial failed");
  m.ls = SUNLinSol_SPGMR(m.x, SUN_PREC_NONE, options.max_krylov, m.ctx);
  if (!m.ls) throw std::runtime_error("GMRES: SUNLinSol_SPGMR failed");
  require(SUNLinSol_SPGMRSetMaxRestarts(m.ls, options.max_restarts), "SetMaxRestarts");
  require(SUNLinSolSetATimes(m.ls, &m, &Impl::atimes), "SetATimes");
  require(SUNLinSolInitialize(m.ls), "Initialize");
  require(SUNLinSolSetup(m.ls, nullptr), "Setup");
}

Gmres::~Gmres() = default;

int Gmres::size() const {
  return impl_->n;
}

GmresResult Gmres::solve(const Operator& A, const Eigen::VectorXd& b, Eigen::VectorXd* y) {
  Impl& m = *impl_;
  if (b.size() != m.n || y->size() != m.n) throw std::invalid_argument("GMRES: size mismatch");
  GmresResult r;
  const double bnorm = b.norm();
  if (bnorm == 0) {
    y->setZero();
    r.converged = true;
    return r;
  }
  view(m.b) = b;
  view(m.x) = *y;
  m.op = &A;
  m.error = nullptr;
  require(SUNLinSolSetZeroGuess(m.ls, SUNFALSE), "SetZeroGuess");
  // SPGMR stops at ||b - A x||_2 < delta (unit scaling vectors).
  const int flag = SUNLinSolSolve(m.ls, nullptr, m.x, m.b, m.opt.tolerance * bnorm);
  m.op = nullptr;
  if (m.error) std::rethrow_exception(m.error);
  *y = view(m.x);
  r.iterations = SUNLinSolNumIters(m.ls);
  r.residual = SUNLinSolResNorm(m.ls) / bnorm;
  r.converged = flag == SUNLS_SUCCESS;
  if (flag < 0 || (flag > 0 && flag != SUNLS_RES_REDUCED && flag != SUNLS_CONV_FAIL))
    throw std::runtime_error("GMRES: SPGMR failed (flag " + std::to_string(flag) + ")");
  return r;
}

}  // namespace capflow::capsule
