#include "capsule/gmres.h"

#include <exception>
#include <memory>
#include <stdexcept>
#include <string>

#include "capsule/sundials_glue.h"

namespace capflow::capsule {

namespace {
using sundials::view;
constexpr const char* kSolver = "GMRES:";
}  // namespace

struct Gmres::Impl {
  int n = 0;
  GmresOptions opt;
  sundials::Context ctx{kSolver};
  sundials::Vector x, b;
  std::unique_ptr<sundials::Spgmr> ls;
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
};

Gmres::Gmres(int n, GmresOptions options) : impl_(std::make_unique<Impl>()) {
  if (n < 1) throw std::invalid_argument("GMRES: the system needs at least one unknown");
  if (options.max_krylov < 1 || options.max_restarts < 0 || !(options.tolerance > 0))
    throw std::invalid_argument("GMRES: need max_krylov >= 1, max_restarts >= 0, tolerance > 0");
  Impl& m = *impl_;
  m.n = n;
  m.opt = options;
  m.x.reset(n, m.ctx, kSolver);
  m.b.reset(n, m.ctx, kSolver);
  m.ls = std::make_unique<sundials::Spgmr>(m.x, options.max_krylov, options.max_restarts, m.ctx,
                                           kSolver);
  SUNLinearSolver ls = m.ls->get();
  sundials::require(SUNLinSolSetATimes(ls, &m, &Impl::atimes), kSolver, "SetATimes");
  sundials::require(SUNLinSolInitialize(ls), kSolver, "Initialize");
  sundials::require(SUNLinSolSetup(ls, nullptr), kSolver, "Setup");
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
  m.b.view() = b;
  m.x.view() = *y;
  SUNLinearSolver ls = m.ls->get();
  m.op = &A;
  m.error = nullptr;
  sundials::require(SUNLinSolSetZeroGuess(ls, SUNFALSE), kSolver, "SetZeroGuess");
  // SPGMR stops at ||b - A x||_2 < delta (unit scaling vectors).
  const int flag = SUNLinSolSolve(ls, nullptr, m.x.get(), m.b.get(), m.opt.tolerance * bnorm);
  m.op = nullptr;
  if (m.error) std::rethrow_exception(m.error);
  *y = m.x.view();
  r.iterations = SUNLinSolNumIters(ls);
  r.residual = SUNLinSolResNorm(ls) / bnorm;
  r.converged = flag == SUNLS_SUCCESS;
  if (flag < 0 || (flag > 0 && flag != SUNLS_RES_REDUCED && flag != SUNLS_CONV_FAIL))
    throw std::runtime_error("GMRES: SPGMR failed (flag " + std::to_string(flag) + ")");
  return r;
}

}  // namespace capflow::capsule
