// capflow/capsule/gmres: restarted GMRES (SUNDIALS SPGMR, modified Gram-Schmidt, no
// preconditioner) for A y = b with A given as a function: the second-kind boundary integral
// equation of viscosity ratio != 1 (capsule/viscosity_ratio.h). SPGMR because SUNDIALS is
// already the solver library of the adaptive steps and the steady solver, and its matrix-free
// interface takes the operator as a callback, with a warm start from y.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>

namespace capflow::capsule {

struct GmresOptions {
  int max_krylov = 30;       // Krylov subspace size before a restart
  int max_restarts = 10;     // restarts after the first cycle
  double tolerance = 1e-10;  // stop when ||b - A y||_2 <= tolerance ||b||_2
};

struct GmresResult {
  int iterations = 0;   // Krylov iterations (operator applications)
  double residual = 0;  // ||b - A y||_2 / ||b||_2 at the end
  bool converged = false;
};

class Gmres {
 public:
  // out = A v (both of the system's size).
  using Operator = std::function<void(const Eigen::VectorXd& v, Eigen::VectorXd& out)>;

  Gmres(int n, GmresOptions options = {});
  ~Gmres();
  Gmres(const Gmres&) = delete;
  Gmres& operator=(const Gmres&) = delete;

  // Solves A y = b starting from *y (the warm start); *y holds the last iterate on return.
  // An exception thrown by A propagates after the solver is left consistent.
  GmresResult solve(const Operator& A, const Eigen::VectorXd& b, Eigen::VectorXd* y);

  int size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace capflow::capsule
