// capflow/capsule/sundials_glue: what the three SUNDIALS users (adaptive_stepper: ARKODE,
// steady_solver: KINSOL, gmres: SPGMR) share - an Eigen view of a serial N_Vector, the flag
// check of a set-up call, and owners of the context, the vectors and the linear solver that free
// them in the right order (members declared context first, freed last).
#pragma once

#include <Eigen/Dense>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

namespace capflow::capsule::sundials {

// The vector's data as an Eigen vector (no copy).
Eigen::Map<Eigen::VectorXd> view(N_Vector v);

// A set-up call's flag: std::runtime_error "<solver> <call> failed (flag N)" when negative
// (SUNDIALS' failures; positive flags are recoverable conditions the caller reads itself).
void require(int flag, const char* solver, const char* call);

// A SUNContext, freed with its owner.
class Context {
 public:
  explicit Context(const char* solver);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  SUNContext get() const { return ctx_; }

 private:
  SUNContext ctx_ = nullptr;
};

// A serial N_Vector of n entries (none until reset), freed with its owner.
class Vector {
 public:
  Vector() = default;
  Vector(long n, const Context& ctx, const char* solver) { reset(n, ctx, solver); }
  ~Vector();
  Vector(const Vector&) = delete;
  Vector& operator=(const Vector&) = delete;
  void reset(long n, const Context& ctx, const char* solver);
  N_Vector get() const { return v_; }
  long size() const { return v_ ? static_cast<long>(N_VGetLength(v_)) : 0; }
  Eigen::Map<Eigen::VectorXd> view() const { return sundials::view(v_); }

 private:
  N_Vector v_ = nullptr;
};

// SPGMR without preconditioning on vectors like `like`, its Krylov subspace max_krylov (and
// max_restarts restarts), freed with its owner.
class Spgmr {
 public:
  Spgmr(const Vector& like, int max_krylov, int max_restarts, const Context& ctx,
        const char* solver);
  ~Spgmr();
  Spgmr(const Spgmr&) = delete;
  Spgmr& operator=(const Spgmr&) = delete;
  SUNLinearSolver get() const { return ls_; }

 private:
  SUNLinearSolver ls_ = nullptr;
};

}  // namespace capflow::capsule::sundials
