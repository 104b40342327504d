// capflow/capsule/sundials_glue: see sundials_glue.h.
#include "capsule/sundials_glue.h"

#include <sunlinsol/sunlinsol_spgmr.h>

#include <stdexcept>
#include <string>

namespace capflow::capsule::sundials {

Eigen::Map<Eigen::VectorXd> view(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(N_VGetLength(v))};
}

void require(int flag, const char* solver, const char* call) {
  if (flag < 0)
    throw std::runtime_error(std::string(solver) + " " + call + " failed (flag " +
                             std::to_string(flag) + ")");
}

Context::Context(const char* solver) {
  require(SUNContext_Create(nullptr, &ctx_), solver, "SUNContext_Create");
}

Context::~Context() {
  if (ctx_) SUNContext_Free(&ctx_);
}

void Vector::reset(long n, const Context& ctx, const char* solver) {
  if (v_) N_VDestroy(v_);
  v_ = N_VNew_Serial(n, ctx.get());
  if (!v_) throw std::runtime_error(std::string(solver) + " N_VNew_Serial failed");
}

Vector::~Vector() {
  if (v_) N_VDestroy(v_);
}

Spgmr::Spgmr(const Vector& like, int max_krylov, int max_restarts, const Context& ctx,
             const char* solver) {
  ls_ = SUNLinSol_SPGMR(like.get(), SUN_PREC_NONE, max_krylov, ctx.get());
  if (!ls_) throw std::runtime_error(std::string(solver) + " SUNLinSol_SPGMR failed");
  require(SUNLinSol_SPGMRSetMaxRestarts(ls_, max_restarts), solver,
          "SUNLinSol_SPGMRSetMaxRestarts");
}

Spgmr::~Spgmr() {
  if (ls_) SUNLinSolFree(ls_);
}

}  // namespace capflow::capsule::sundials
