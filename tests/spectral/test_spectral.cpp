// Spectral toolkit: exactness on polynomials (the defining property of each rule/operator).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "spectral/spectral.h"

using namespace capflow::spectral;

namespace {
double monomial_integral(int k) {
  return (k % 2 == 1) ? 0.0 : 2.0 / (k + 1.0);
}

double legendre_square_sum(const Rule& r, int k) {
  double s = 0;
  for (int i = 0; i < r.x.size(); ++i) {
    double p;
    legendre(k, r.x[i], &p, nullptr);
    s += r.w[i] * p * p;
  }
  return s;
}

// Random polynomial of given degree with coefficients in [-1, 1] (Horner evaluation).
struct Poly {
  std::vector<double> c;
  double operator()(double x) const {
    double r = 0;
    for (int k = static_cast<int>(c.size()) - 1; k >= 0; --k) r = r * x + c[k];
    return r;
  }
  double derivative(double x) const {
    double r = 0;
    for (int k = static_cast<int>(c.size()) - 1; k >= 1; --k) r = r * x + k * c[k];
    return r;
  }
};
Poly random_poly(int degree, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Poly p;
  for (int k = 0; k <= degree; ++k) p.c.push_back(u(rng));
  return p;
}
}  // namespace

TEST(Spectral, GaussLegendreExactToDegree2nMinus1) {
  for (int n = 1; n <= 64; ++n) {
    const Rule r = gauss_legendre(n);
    for (int i = 1; i < n; ++i) ASSERT_LT(r.x[i - 1], r.x[i]);
    for (int k = 0; k <= 2 * n - 1; ++k) {
      const double q = (r.w.array() * r.x.array().pow(k)).sum();
      ASSERT_NEAR(q, monomial_integral(k), 1e-13) << "n=" << n << " k=" << k;
    }
    // Sharp: P_n^2 (degree 2n) vanishes at every node but integrates to 2/(2n+1).
    EXPECT_NEAR(legendre_square_sum(r, n), 0.0, 1e-20) << "n=" << n;
  }
}

TEST(Spectral, GaussLobattoExactToDegree2nMinus3) {
  for (int n = 2; n <= 64; ++n) {
    const Rule r = gauss_lobatto(n);
    ASSERT_EQ(r.x[0], -1.0);
    ASSERT_EQ(r.x[n - 1], 1.0);
    for (int i = 1; i < n; ++i) ASSERT_LT(r.x[i - 1], r.x[i]);
    for (int k = 0; k <= 2 * n - 3; ++k) {
      const double q = (r.w.array() * r.x.array().pow(k)).sum();
      ASSERT_NEAR(q, monomial_integral(k), 1e-13) << "n=" << n << " k=" << k;
    }
    // Sharp: the rule misses INT P_{n-1}^2 = 2/(2n-1) (degree 2n-2); it gives 2/(n-1).
    EXPECT_NEAR(legendre_square_sum(r, n - 1), 2.0 / (n - 1.0), 1e-12) << "n=" << n;
  }
}

TEST(Spectral, RejectsBadSizes) {
  EXPECT_THROW(gauss_legendre(0), std::invalid_argument);
  EXPECT_THROW(gauss_lobatto(1), std::invalid_argument);
  EXPECT_THROW(gauss_legendre(257), std::invalid_argument);
  Eigen::VectorXd dup(3);
  dup << 0.0, 0.5, 0.5;
  EXPECT_THROW(barycentric_weights(dup), std::invalid_argument);
}

TEST(Spectral, InterpolationAndDifferentiationExactOnDegreeNbMinus1) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int nb = 2; nb <= 32; ++nb) {
    const VectorXd x = gauss_lobatto(nb).x;
    const Poly p = random_poly(nb - 1, rng);
    VectorXd f(nb), df(nb);
    for (int i = 0; i < nb; ++i) {
      f[i] = p(x[i]);
      df[i] = p.derivative(x[i]);
    }
    VectorXd t(7);
    for (int k = 0; k < 5; ++k) t[k] = u(rng);
    t[5] = x[0];               // a node exactly
    t[6] = x[nb / 2] + 1e-12;  // extremely close to a node
    const VectorXd ft = interpolation_matrix(x, t) * f;
    const VectorXd dft = derivative_matrix(x, t) * f;
    const VectorXd dfn = differentiation_matrix(x) * f;
    for (int k = 0; k < t.size(); ++k) {
      ASSERT_NEAR(ft[k], p(t[k]), 1e-13) << "nb=" << nb;
      ASSERT_NEAR(dft[k], p.derivative(t[k]), 1e-11 * nb * nb) << "nb=" << nb << " k=" << k;
    }
    for (int i = 0; i < nb; ++i) ASSERT_NEAR(dfn[i], df[i], 1e-12 * nb * nb) << "nb=" << nb;
    // Differentiation annihilates constants exactly (negative-sum diagonal).
    EXPECT_LT((differentiation_matrix(x) * VectorXd::Ones(nb)).cwiseAbs().maxCoeff(),
              1e-15 * nb * nb);
  }
}

TEST(Spectral, InterpolationOfNonPolynomialConvergesExponentially) {
  // Runge-free entire function: error must fall by orders of magnitude with n.
  double prev = 1.0;
  for (int nb : {6, 10, 14, 18}) {
    const VectorXd x = gauss_lobatto(nb).x;
    VectorXd f = x.array().exp().matrix();
    VectorXd t = VectorXd::LinSpaced(41, -1, 1);
    const VectorXd e = interpolation_matrix(x, t) * f - VectorXd(t.array().exp());
    const double err = e.cwiseAbs().maxCoeff();
    EXPECT_LT(err, std::max(prev * 1e-2, 1e-14)) << "nb=" << nb;
    prev = std::max(err, 1e-15);
  }
}

TEST(Spectral, TensorProductExactOnDegreeNbMinus1) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int nb : {3, 8, 13}) {
    const VectorXd x = gauss_lobatto(nb).x;
    const Poly p = random_poly(nb - 1, rng), q = random_poly(nb - 1, rng);
    MatrixXd v(nb, nb);
    for (int i = 0; i < nb; ++i)
      for (int j = 0; j < nb; ++j) v(i, j) = p(x[i]) * q(x[j]) + x[i] * x[j];
    for (int k = 0; k < 10; ++k) {
      const double s = u(rng), t = u(rng);
      EXPECT_NEAR(tensor_evaluate(x, v, s, t), p(s) * q(t) + s * t, 1e-13);
    }
    const VectorXd sa = VectorXd::LinSpaced(5, -1, 1), tb = VectorXd::LinSpaced(4, -0.9, 0.9);
    const MatrixXd r = tensor_resample(x, v, sa, tb);
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 4; ++b) EXPECT_NEAR(r(a, b), p(sa[a]) * q(tb[b]) + sa[a] * tb[b], 1e-13);
  }
}

// The O(n) barycentric derivative keeps full accuracy at every distance from a node: the
// cancellation of l_j' = l_j (T - 1/(t - x_j)) near x_m affects only j = m, which is taken from
// sum_j l_j' = 0. Derivative of a random degree n-1 polynomial at x_m +- delta, delta from 1e-1
// down to 1e-14, against its exact derivative; and the basis derivatives sum to zero.
TEST(Spectral, BasisDerivativeAccurateAtAnyDistanceFromANode) {
  std::mt19937 rng(777);
  for (int nb : {4, 8, 12, 16, 24}) {
    const VectorXd x = gauss_lobatto(nb).x;
    const VectorXd bw = barycentric_weights(x);
    const Poly p = random_poly(nb - 1, rng);
    double worst = 0, worst_sum = 0;
    std::vector<double> l(nb), dl(nb);
    for (int m = 0; m < nb; ++m)
      for (int e = 1; e <= 14; ++e)
        for (double sign : {-1.0, 1.0}) {
          const double t = x[m] + sign * std::pow(10.0, -e);
          if (t < -1.0 || t > 1.0) continue;
          lagrange_basis(x, bw, t, l.data(), dl.data());
          double d = 0, s = 0, scale = 0;
          for (int j = 0; j < nb; ++j) {
            d += dl[j] * p(x[j]);
            s += dl[j];
            scale = std::max(scale, std::abs(dl[j]));
          }
          worst = std::max(worst, std::abs(d - p.derivative(t)));
          worst_sum = std::max(worst_sum, std::abs(s) / scale);
        }
    std::printf("nb=%d: max |p'(t) - sum l_j'(t) p_j| = %.1e, max |sum l_j'| / max |l_j'| = %.1e\n",
                nb, worst, worst_sum);
    EXPECT_LT(worst, 2e-14 * nb * nb) << "nb=" << nb;
    EXPECT_LT(worst_sum, 1e-14) << "nb=" << nb;
  }
}

// The batch product form of the bases: exact on polynomials of degree nb-1 (value and
// derivative) at random points, at the nodes themselves and at 1e-1 .. 1e-14 from them, and
// equal to the single-point barycentric form.
TEST(Spectral, BatchBasesExactOnPolynomialsAtAndNearNodes) {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int nb : {2, 4, 8, 12, 16, 24, 32}) {
    const VectorXd x = gauss_lobatto(nb).x;
    const VectorXd bw = barycentric_weights(x), c = product_weights(x);
    const Poly p = random_poly(nb - 1, rng);
    std::vector<double> t;
    for (int k = 0; k < 50; ++k) t.push_back(u(rng));
    for (int m = 0; m < nb; ++m) {
      t.push_back(x[m]);
      for (int e = 1; e <= 14; ++e)
        for (double sign : {-1.0, 1.0}) {
          const double tt = x[m] + sign * std::pow(10.0, -e);
          if (tt >= -1.0 && tt <= 1.0) t.push_back(tt);
        }
    }
    const int np = static_cast<int>(t.size());
    const long ld = np + 3;
    std::vector<double> L(ld * nb), dL(ld * nb), l(nb), dl(nb);
    lagrange_bases(x, c, t.data(), np, L.data(), dL.data(), ld);
    double err_v = 0, err_d = 0, err_single = 0;
    for (int q = 0; q < np; ++q) {
      double v = 0, d = 0;
      lagrange_basis(x, bw, t[q], l.data(), dl.data());
      for (int j = 0; j < nb; ++j) {
        v += L[q + j * ld] * p(x[j]);
        d += dL[q + j * ld] * p(x[j]);
        err_single = std::max(err_single, std::abs(L[q + j * ld] - l[j]) +
                                              std::abs(dL[q + j * ld] - dl[j]) / (nb * nb));
      }
      err_v = std::max(err_v, std::abs(v - p(t[q])));
      err_d = std::max(err_d, std::abs(d - p.derivative(t[q])));
    }
    std::printf("nb=%d (%d points): value %.1e, derivative %.1e, vs lagrange_basis %.1e\n", nb, np,
                err_v, err_d, err_single);
    EXPECT_LT(err_v, 1e-14 * nb) << "nb=" << nb;
    EXPECT_LT(err_d, 2e-14 * nb * nb) << "nb=" << nb;
    EXPECT_LT(err_single, 1e-14 * nb) << "nb=" << nb;
  }
  EXPECT_THROW(
      lagrange_bases(gauss_lobatto(4).x, VectorXd::Ones(3), nullptr, 0, nullptr, nullptr, 0),
      std::invalid_argument);
}

// chebyshev_matrix: the Chebyshev coefficients of a polynomial of degree < nb are recovered from
// its values at the nodes, and the Chebyshev series (with the derivative k U_{k-1}) reproduces the
// polynomial and its derivative everywhere in [-1, 1].
TEST(Spectral, ChebyshevCoefficientsExactOnDegreeNbMinus1) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int nb : {2, 3, 6, 10, 14, 18, 24}) {
    const VectorXd x = gauss_lobatto(nb).x;
    const MatrixXd C = chebyshev_matrix(x);
    VectorXd c(nb), v(nb);
    for (int k = 0; k < nb; ++k) c[k] = u(rng);
    for (int j = 0; j < nb; ++j) {
      v[j] = 0;
      for (int k = 0; k < nb; ++k) v[j] += c[k] * std::cos(k * std::acos(x[j]));
    }
    const double err_c = (C * v - c).cwiseAbs().maxCoeff();
    const Poly p = random_poly(nb - 1, rng);
    VectorXd pv(nb);
    for (int j = 0; j < nb; ++j) pv[j] = p(x[j]);
    const VectorXd pc = C * pv;
    double err_v = 0, err_d = 0;
    for (int q = 0; q <= 200; ++q) {
      const double t = -1.0 + q * 0.01;
      // T_k by the three-term recurrence, T_k' = k U_{k-1}
      double tm = 1.0, tk = t, um = 0.0, uk = 1.0, val = pc[0], der = 0.0;
      for (int k = 1; k < nb; ++k) {
        val += pc[k] * tk;
        der += k * pc[k] * uk;
        const double tn = 2 * t * tk - tm, un = 2 * t * uk - um;
        tm = tk;
        tk = tn;
        um = uk;
        uk = un;
      }
      err_v = std::max(err_v, std::abs(val - p(t)));
      err_d = std::max(err_d, std::abs(der - p.derivative(t)));
    }
    std::printf("nb=%d: coefficients %.1e, values %.1e, derivatives %.1e\n", nb, err_c, err_v,
                err_d);
    EXPECT_LT(err_c, 1e-14 * nb) << "nb=" << nb;
    EXPECT_LT(err_v, 1e-14 * nb) << "nb=" << nb;
    EXPECT_LT(err_d, 2e-14 * nb * nb) << "nb=" << nb;
  }
}
