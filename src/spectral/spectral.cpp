#include "spectral/spectral.h"
#include "spectral/target_clones.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace capflow::spectral {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxN = 256;

void check_n(int n, int lo, const char* what) {
  if (n < lo || n > kMaxN)
    throw std::invalid_argument(std::string(what) + ": n must be in [" + std::to_string(lo) + ", " +
                                std::to_string(kMaxN) + "], got " + std::to_string(n));
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

void lagrange_basis(const VectorXd& nodes, const VectorXd& bw, double t, double* l, double* dl) {
  const int n = static_cast<int>(nodes.size());
  check_n(n, 1, "lagrange_basis");
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
  // Barycentric form: l_j(t) = a_j / S, a_j = w_j/(t-x_j), S = sum_k a_k. Its derivative is
  //   l_j'(t) = l_j(t) (T - 1/(t-x_j)),  T = sum_k l_k(t)/(t-x_k).
  // Near a node x_m, T and 1/(t-x_m) are both ~1/(t-x_m) and their difference cancels
  // (error ~ eps/|t-x_m|) - but only for j = m: for j != m the product l_j (T - 1/(t-x_j)) of
  // a small and a large factor is accurate. So l_m' is taken from sum_j l_j' = 0 instead
  // (O(n), accurate to ~1e-14 at any distance from the nodes: tests/spectral).
  double s = 0.0, nearest = 3.0;
  int m = 0;
  double inv[kMaxN];
  for (int j = 0; j < n; ++j) {
    const double d = t - nodes[j];
    if (std::abs(d) < nearest) {
      nearest = std::abs(d);
      m = j;
    }
    inv[j] = 1.0 / d;
    l[j] = bw[j] * inv[j];
    s += l[j];
  }
  double T = 0.0;
  for (int j = 0; j < n; ++j) {
    l[j] /= s;
    T += l[j] * inv[j];
  }
  if (!dl) return;
  double sum = 0.0;
  for (int j = 0; j < n; ++j) {
    dl[j] = l[j] * (T - inv[j]);
    sum += dl[j];
  }
  dl[m] -= sum;
}

VectorXd product_weights(const VectorXd& nodes) {
  const int n = static_cast<int>(nodes.size());
  check_n(n, 1, "product_weights");
  VectorXd c(n);
  for (int j = 0; j < n; ++j) {
    double prod = 1.0;
    for (int k = 0; k < n; ++k)
      if (k != j) prod *= nodes[j] - nodes[k];
    if (prod == 0.0) throw std::invalid_argument("product_weights: coincident nodes");
    c[j] = 1.0 / prod;
  }
  return c;
}

// Compiled twice (x86-64-v3 with AVX2/FMA and the default), chosen at load time: the stokes
// special quadrature rules evaluate their bases with it on every call.
CAPFLOW_TARGET_CLONES("arch=x86-64-v3", "default")
void lagrange_bases(const VectorXd& nodes, const VectorXd& c, const double* t, int np, double* L,
                    double* dL, long ld) {
  const int n = static_cast<int>(nodes.size());
  if (c.size() != n || ld < np) throw std::invalid_argument("lagrange_bases: bad sizes");
  thread_local std::vector<double> scratch;
  if (scratch.size() < 2 * static_cast<size_t>(np)) scratch.resize(2 * static_cast<size_t>(np));
  double* __restrict P = scratch.data();  // running product prod_{k < j} (t - x_k), then suffix
  double* __restrict dP = P + np;         // its derivative
  const double* __restrict tp = t;
  // Prefix pass: column j <- prod_{k < j} (t - x_k) and its derivative.
  for (int p = 0; p < np; ++p) {
    P[p] = 1.0;
    dP[p] = 0.0;
  }
  for (int j = 0; j < n; ++j) {
    double* __restrict Lj = L + j * ld;
    double* __restrict dLj = dL + j * ld;
    const double xj = nodes[j];
#pragma omp simd
    for (int p = 0; p < np; ++p) {
      Lj[p] = P[p];
      dLj[p] = dP[p];
      const double d = tp[p] - xj;
      dP[p] = dP[p] * d + P[p];
      P[p] *= d;
    }
  }
  // Suffix pass: times prod_{k > j} (t - x_k) (product rule for the derivative) and c_j.
  for (int p = 0; p < np; ++p) {
    P[p] = 1.0;
    dP[p] = 0.0;
  }
  for (int j = n - 1; j >= 0; --j) {
    double* __restrict Lj = L + j * ld;
    double* __restrict dLj = dL + j * ld;
    const double xj = nodes[j], cj = c[j];
#pragma omp simd
    for (int p = 0; p < np; ++p) {
      dLj[p] = cj * (dLj[p] * P[p] + Lj[p] * dP[p]);
      Lj[p] = cj * Lj[p] * P[p];
      const double d = tp[p] - xj;
      dP[p] = dP[p] * d + P[p];
      P[p] *= d;
    }
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

MatrixXd chebyshev_matrix(const VectorXd& nodes) {
  const int n = static_cast<int>(nodes.size());
  const VectorXd bw = barycentric_weights(nodes);
  // c_k = (2 - delta_k0) / n sum_q l_j(y_q) T_k(y_q), y_q = cos((q + 1/2) pi / n)
  MatrixXd c = MatrixXd::Zero(n, n);
  std::vector<double> l(n);
  for (int q = 0; q < n; ++q) {
    const double th = (q + 0.5) * kPi / n;
    lagrange_basis(nodes, bw, std::cos(th), l.data(), nullptr);
    for (int k = 0; k < n; ++k) {
      const double tk = std::cos(k * th) * (k == 0 ? 1.0 : 2.0) / n;
      for (int j = 0; j < n; ++j) c(k, j) += l[j] * tk;
    }
  }
  return c;
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
