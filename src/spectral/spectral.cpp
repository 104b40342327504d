#include "spectral/spectral.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace capflow::spectral {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxN = 256;

void check_n(int n, int lo, const char* what) {
  if (n < lo || n > kMaxN)
    throw std::invalid_argument(std::string(what) + ": n must be in [" + std::to_string(lo) +
                                ", " + std::to_string(kMaxN) + "], got " + std::to_string(n));
}
}  // namespace

void legendre(int n, double x, double* p, double* dp) {
  double p0 = 1.0, p1 = x;
  if (n == 0) {
    *p = 1.0;
    if (dp) *dp = 0.0;
    return;
  }
  for (int k = 2; k <= n; ++k) {
    const double pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
    p0 = p1;
    p1 = pk;
  }
  *p = p1;
  if (dp) {
    // P_n' = n (x P_n - P_{n-1}) / (x^2 - 1), with the endpoint limit n(n+1)/2 * (+-1)^(n+1).
    if (std::abs(std::abs(x) - 1.0) < 1e-14)
      *dp = 0.5 * n * (n + 1.0) * ((x > 0 || n % 2 == 1) ? 1.0 : -1.0);
    else
      *dp = n * (x * p1 - p0) / (x * x - 1.0);
  }
}

Rule gauss_legendre(int n) {
  check_n(n, 1, "gauss_legendre");
  Rule r{VectorXd(n), VectorXd(n)};
  for (int i = 0; i < (n + 1) / 2; ++i) {
    // Tricomi's initial guess, then Newton on P_n.
    double x = -std::cos(kPi * (i + 0.75) / (n + 0.5));
    double p = 0, dp = 1;
    for (int it = 0; it < 100; ++it) {
      legendre(n, x, &p, &dp);
      const double dx = p / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    legendre(n, x, &p, &dp);
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    r.x[i] = x;
    r.x[n - 1 - i] = -x;
    r.w[i] = r.w[n - 1 - i] = w;
  }
  if (n % 2 == 1) r.x[n / 2] = 0.0;
  return r;
}

Rule gauss_lobatto(int n) {
  check_n(n, 2, "gauss_lobatto");
  // Interior nodes are the roots of P_{n-1}'; weights 2 / (n (n-1) P_{n-1}(x)^2).
  const int m = n - 1;
  Rule r{VectorXd(n), VectorXd(n)};
  r.x[0] = -1.0;
  r.x[n - 1] = 1.0;
  r.w[0] = r.w[n - 1] = 2.0 / (n * (n - 1.0));
  for (int i = 1; i < (n + 1) / 2; ++i) {
    // Chebyshev-Gauss-Lobatto initial guess; Newton on q = P_m' using
    // q' = (2x P_m' - m(m+1) P_m) / (1 - x^2).
    double x = -std::cos(kPi * i / m);
    for (int it = 0; it < 100; ++it) {
      double p, dp;
      legendre(m, x, &p, &dp);
      const double d2p = (2.0 * x * dp - m * (m + 1.0) * p) / (1.0 - x * x);
      const double dx = dp / d2p;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    double p;
    legendre(m, x, &p, nullptr);
    r.x[i] = x;
    r.x[n - 1 - i] = -x;
    r.w[i] = r.w[n - 1 - i] = 2.0 / (n * (n - 1.0) * p * p);
  }
  if (n % 2 == 1) {
    double p;
    legendre(m, 0.0, &p, nullptr);
    r.x[n / 2] = 0.0;
    r.w[n / 2] = 2.0 / (n * (n - 1.0) * p * p);
  }
  return r;
}

VectorXd barycentric_weights(const VectorXd& nodes) {
  const int n = static_cast<int>(nodes.size());
  if (n < 1) throw std::invalid_argument("barycentric_weights: no nodes");
  VectorXd w(n);
  for (int j = 0; j < n; ++j) {
    double prod = 1.0;
    for (int k = 0; k < n; ++k) {
      if (k == j) continue;
      const double d = nodes[j] - nodes[k];
      if (d == 0.0) throw std::invalid_argument("barycentric_weights: coincident nodes");
      prod *= d;
    }
    w[j] = 1.0 / prod;
  }
  return w / w.cwiseAbs().maxCoeff();
}

void lagrange_basis(const VectorXd& nodes, const VectorXd& bw, double t, double* l,
                    double* dl) {
  const int n = static_cast<int>(nodes.size());
  for (int j = 0; j < n; ++j) {
    if (t == nodes[j]) {
      // At a node: l is a unit vector; l_k'(x_j) comes from the differentiation formula.
      for (int k = 0; k < n; ++k) l[k] = (k == j) ? 1.0 : 0.0;
      if (dl) {
        double diag = 0.0;
        for (int k = 0; k < n; ++k) {
          if (k == j) continue;
          dl[k] = (bw[k] / bw[j]) / (nodes[j] - nodes[k]);
          diag -= dl[k];
        }
        dl[j] = diag;
      }
      return;
    }
  }
  // Barycentric form p(t) = sum a_j f_j / sum a_j, a_j = w_j/(t-x_j); its derivative
  // p'(t) = sum_j a_j (p(t) - f_j)/(t - x_j) / sum a_j keeps full accuracy near nodes.
  double s = 0.0;
  for (int j = 0; j < n; ++j) {
    l[j] = bw[j] / (t - nodes[j]);
    s += l[j];
  }
  for (int j = 0; j < n; ++j) l[j] /= s;
  if (!dl) return;
  double nearest = 2.0;
  for (int j = 0; j < n; ++j) nearest = std::min(nearest, std::abs(t - nodes[j]));
  if (nearest < 1e-2) {
    // Near a node the closed form below cancels catastrophically (error ~ eps/|t - x_j|).
    // Use instead that p' (degree n-2) equals its own interpolant:
    //   l_k'(t) = sum_m l_m(t) D(m, k),  D(m, k) = l_k'(x_m)   (exact, O(n^2)).
    for (int k = 0; k < n; ++k) dl[k] = 0.0;
    for (int m = 0; m < n; ++m) {
      double diag = 0.0;
      for (int k = 0; k < n; ++k) {
        if (k == m) continue;
        const double dmk = (bw[k] / bw[m]) / (nodes[m] - nodes[k]);
        dl[k] += l[m] * dmk;
        diag -= dmk;
      }
      dl[m] += l[m] * diag;
    }
    return;
  }
  {
    // l_k'(t) = (sum_j a_j (l_k(t) - delta_jk)/(t-x_j)) / S,  a_j = w_j/(t-x_j)
    double q = 0.0;  // sum_j a_j/(t-x_j) / S
    for (int j = 0; j < n; ++j) q += (bw[j] / (t - nodes[j])) / (t - nodes[j]);
    q /= s;
    for (int k = 0; k < n; ++k) dl[k] = l[k] * q - (bw[k] / (t - nodes[k])) / (t - nodes[k]) / s;
  }
}

MatrixXd interpolation_matrix(const VectorXd& nodes, const VectorXd& targets) {
  const VectorXd bw = barycentric_weights(nodes);
  const int n = static_cast<int>(nodes.size());
  MatrixXd m(targets.size(), n);
  std::vector<double> l(n);
  for (int k = 0; k < targets.size(); ++k) {
    lagrange_basis(nodes, bw, targets[k], l.data(), nullptr);
    for (int j = 0; j < n; ++j) m(k, j) = l[j];
  }
  return m;
}

MatrixXd derivative_matrix(const VectorXd& nodes, const VectorXd& targets) {
  const VectorXd bw = barycentric_weights(nodes);
  const int n = static_cast<int>(nodes.size());
  MatrixXd m(targets.size(), n);
  std::vector<double> l(n), dl(n);
  for (int k = 0; k < targets.size(); ++k) {
    lagrange_basis(nodes, bw, targets[k], l.data(), dl.data());
    for (int j = 0; j < n; ++j) m(k, j) = dl[j];
  }
  return m;
}

MatrixXd differentiation_matrix(const VectorXd& nodes) {
  const VectorXd bw = barycentric_weights(nodes);
  const int n = static_cast<int>(nodes.size());
  MatrixXd d = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    double diag = 0.0;
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      d(i, j) = (bw[j] / bw[i]) / (nodes[i] - nodes[j]);
      diag -= d(i, j);  // negative-sum trick: rows annihilate constants exactly
    }
    d(i, i) = diag;
  }
  return d;
}

double tensor_evaluate(const VectorXd& nodes, const MatrixXd& v, double s, double t) {
  const VectorXd bw = barycentric_weights(nodes);
  const int n = static_cast<int>(nodes.size());
  std::vector<double> ls(n), lt(n);
  lagrange_basis(nodes, bw, s, ls.data(), nullptr);
  lagrange_basis(nodes, bw, t, lt.data(), nullptr);
  double r = 0.0;
  for (int j = 0; j < n; ++j) {
    double c = 0.0;
    for (int i = 0; i < n; ++i) c += v(i, j) * ls[i];
    r += c * lt[j];
  }
  return r;
}

MatrixXd tensor_resample(const VectorXd& nodes, const MatrixXd& v, const VectorXd& sa,
                         const VectorXd& tb) {
  const MatrixXd is = interpolation_matrix(nodes, sa);
  const MatrixXd it = interpolation_matrix(nodes, tb);
  return is * v * it.transpose();
}

}  // namespace capflow::spectral
