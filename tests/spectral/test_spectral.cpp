// Spectral toolkit: exactness on polynomials (the defining property of each rule/operator).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "spectral/spectral.h"

using namespace capflow::spectral;

namespace {
double monomial_integral(int k) { return (k % 2 == 1) ? 0.0 : 2.0 / (k + 1.0); }

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
    t[5] = x[0];  // a node exactly
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
    EXPECT_LT((differentiation_matrix(x) * VectorXd::Ones(nb)).cwiseAbs().maxCoeff(), 1e-15 * nb * nb);
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
      for (int b = 0; b < 4; ++b)
        EXPECT_NEAR(r(a, b), p(sa[a]) * q(tb[b]) + sa[a] * tb[b], 1e-13);
  }
}
