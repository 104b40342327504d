// Study program (not a timing): the spectrum of a stiff membrane's velocity Jacobian, and what it
// means for the time integrators (docs/performance.md, "Red blood cells").
//
// The red blood cell in shear (Evans-Fung, axis along the flow, Skalak C = 10, Eb = 5e-3 about
// its own shape, Ca = 0.1) is advanced from rest by `steps` RK4 steps of `dt`; then the Jacobian
// J of the node velocities on the flow's symmetry unknowns (the state space of a run) is taken
// by forward differences. Printed:
//   * the spectral radius and the eigenvalues with the largest imaginary parts;
//   * for the damped Runge-Kutta-Chebyshev polynomials (damping eps, s stages), the largest h
//     with |R_s(h lambda)| <= 1 for every eigenvalue with |lambda| >= 1 (sampled at h/4, h/2,
//     3h/4 and h; the slower modes are the flow's, their steps set by accuracy), and the
//     velocity evaluations per unit time that buys (s / h);
//   * the GMRES iterations (no preconditioner) that the backward-Euler system (I - h J) v = b
//     needs to a relative residual of 1e-3, for a random b: what a Newton-Krylov implicit step
//     would pay per Newton iteration.
//
//   membrane_spectrum [NE NB steps dt]      (default 10 12 400 1e-4: about 4 min on 2 cores)
#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/IterativeSolvers>

#include <algorithm>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "capsule/capsule.h"
#include "capsule/chebyshev_stepper.h"
#include "red_cell.h"

using namespace capflow;
using cplx = std::complex<double>;

namespace {

double max_amplification(const std::vector<cplx>& lambda, double h, int s, double eps) {
  double worst = 0;
  for (const cplx& l : lambda)
    worst = std::max(worst, std::abs(capsule::ChebyshevStepper::stability_function(s, h * l, eps)));
  return worst;
}

double largest_stable_step(const std::vector<cplx>& lambda, double rho, int s, double eps) {
  const auto stable = [&](double h) {
    for (double f : {0.25, 0.5, 0.75, 1.0})
      if (max_amplification(lambda, f * h, s, eps) > 1.0 + 1e-9) return false;
    return true;
  };
  double lo = 0, hi = 2.0 * s * s / rho;
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

int main(int argc, char** argv) {
  const int ne = argc > 1 ? std::atoi(argv[1]) : 10, nb = argc > 2 ? std::atoi(argv[2]) : 12;
  const int steps = argc > 3 ? std::atoi(argv[3]) : 400;
  const double dt = argc > 4 ? std::atof(argv[4]) : 1e-4;
  const geometry::Mesh mesh(ne, nb);
  const double ca = 0.1;
  const capsule::Capsule cap = bench::red_cell(mesh, steps, dt, ca);

  // The Jacobian on the symmetry unknowns: perturb a target, expand by the symmetry, restrict.
  const std::vector<int>& targets = cap.symmetry().targets();
  const int n = 3 * static_cast<int>(targets.size());
  const auto reduce = [&](const Eigen::Matrix3Xd& x) {
    Eigen::VectorXd y(n);
    for (size_t k = 0; k < targets.size(); ++k) y.segment<3>(3 * k) = x.col(targets[k]);
    return y;
  };
  const auto velocity = [&](const Eigen::VectorXd& y) {
    Eigen::Matrix3Xd x;
    cap.symmetry().expand(Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, n / 3), &x);
    return reduce(cap.velocity(x, ca));
  };
  const Eigen::VectorXd y0 = reduce(cap.positions());
  const Eigen::VectorXd u0 = velocity(y0);
  const double d = 1e-7;
  Eigen::MatrixXd J(n, n);
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd y = y0;
    y(j) += d;
    J.col(j) = (velocity(y) - u0) / d;
  }
  std::printf("red cell NE %d NB %d at t = %g: %d unknowns\n", ne, nb, cap.time(), n);

  const Eigen::VectorXcd ev = Eigen::EigenSolver<Eigen::MatrixXd>(J, false).eigenvalues();
  std::vector<cplx> lambda(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) lambda[k] = ev(k);
  double rho = 0;
  for (const cplx& l : lambda) rho = std::max(rho, std::abs(l));
  std::sort(lambda.begin(), lambda.end(),
            [](const cplx& a, const cplx& b) { return std::abs(a.imag()) > std::abs(b.imag()); });
  std::printf("spectral radius %.4g; largest |Im|:", rho);
  // The slow modes (|lambda| < 1: the flow's own time scale, one of them growing - the tumble)
  // limit the steps by accuracy, not stability: the stability scan leaves them out.
  std::vector<cplx> stiff;
  for (const cplx& l : lambda)
    if (std::abs(l) >= 1.0) stiff.push_back(l);
  for (int k = 0; k < 6; k += 2) std::printf("  %.4g +- %.4gi", lambda[k].real(), std::abs(lambda[k].imag()));
  std::printf("\n\n| eps | s | largest stable h | evaluations per unit time |\n|---:|---:|---:|---:|\n");
  for (double eps : {2.0 / 13.0, 1.0, 4.0, 16.0, 64.0})
    for (int s : {8, 12, 16, 25, 40}) {
      const double h = largest_stable_step(stiff, rho, s, eps);
      std::printf("| %.3g | %d | %.3e | %.0f |\n", eps, s, h, s / h);
    }
  std::printf("Cash-Karp at its real stability limit (3.73 / rho): %.0f evaluations per unit time\n\n",
              6.0 / (3.7344 / rho));

  std::printf("| h | GMRES iterations for (I - h J) v = b to 1e-3 |\n|---:|---:|\n");
  const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
  for (double h : {0.005, 0.01, 0.02, 0.05}) {
    const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n) - h * J;
    Eigen::GMRES<Eigen::MatrixXd, Eigen::IdentityPreconditioner> gmres(A);
    gmres.set_restart(n);
    gmres.setTolerance(1e-3);
    gmres.setMaxIterations(n);
    const Eigen::VectorXd v = gmres.solve(b);
    std::printf("| %g | %ld (residual %.1e) |\n", h, static_cast<long>(gmres.iterations()),
                (A * v - b).norm() / b.norm());
  }
  return 0;
}
