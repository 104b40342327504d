// Pointwise checks of the membrane laws: Cartesian vs principal forms, energy consistency,
// uniaxial stretch, small-strain moduli, option validation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "membrane_test_util.h"

namespace capflow::membrane {
namespace {

using testing::all_laws;
using testing::label;

Eigen::Matrix3d random_rotation(std::mt19937& gen) {
  std::normal_distribution<double> nd;
  Eigen::Quaterniond q(nd(gen), nd(gen), nd(gen), nd(gen));
  return q.normalized().toRotationMatrix();
}

// Deformation with principal stretches (l1, l2), reference tangents non-orthogonal in a random
// plane, current plane randomly rotated.
struct Sample {
  Vector3d T1, T2, t1, t2, d1, d2;
  Eigen::Matrix3d P_ref;
};

Sample make_sample(std::mt19937& gen, double l1, double l2) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix3d Q0 = random_rotation(gen), Q1 = random_rotation(gen);
  const Vector3d e1 = Q0.col(0), e2 = Q0.col(1);
  const double phi = 3.0 * u(gen);
  const Vector3d E1 = std::cos(phi) * e1 + std::sin(phi) * e2;
  const Vector3d E2 = -std::sin(phi) * e1 + std::cos(phi) * e2;
  Sample s;
  s.d1 = Q1.col(0);
  s.d2 = Q1.col(1);
  const Eigen::Matrix3d F = l1 * s.d1 * E1.transpose() + l2 * s.d2 * E2.transpose();
  s.T1 = (1.0 + 0.3 * u(gen)) * e1 + 0.4 * u(gen) * e2;
  s.T2 = 0.4 * u(gen) * e1 + (1.0 + 0.3 * u(gen)) * e2;
  s.t1 = F * s.T1;
  s.t2 = F * s.T2;
  s.P_ref = Eigen::Matrix3d::Identity() - Q0.col(2) * Q0.col(2).transpose();
  return s;
}

TEST(MembraneLaw, CartesianMatchesPrincipalForRandomStretches) {
  std::mt19937 gen(20240611);
  std::uniform_real_distribution<double> stretch(0.5, 2.5);
  double worst = 0;
  for (const auto& law : all_laws()) {
    for (int trial = 0; trial < 200; ++trial) {
      const double l1 = stretch(gen), l2 = stretch(gen);
      const Sample s = make_sample(gen, l1, l2);
      const PointKinematics k = point_kinematics(s.T1, s.T2, s.t1, s.t2);
      const Eigen::Matrix3d tau = tension_tensor(*law, k);
      const double p1 = law->principal_tension(l1, l2), p2 = law->principal_tension(l2, l1);
      const Eigen::Matrix3d expect = p1 * s.d1 * s.d1.transpose() + p2 * s.d2 * s.d2.transpose();
      const double scale = std::max({std::abs(p1), std::abs(p2), 1.0});
      const double err = (tau - expect).cwiseAbs().maxCoeff() / scale;
      worst = std::max(worst, err);
      ASSERT_LT(err, 1e-12) << label(*law) << " l1=" << l1 << " l2=" << l2;
      // Kinematics: B, Js, I1, A = F P_ref.
      const Eigen::Matrix3d B =
          l1 * l1 * s.d1 * s.d1.transpose() + l2 * l2 * s.d2 * s.d2.transpose();
      EXPECT_LT((k.B - B).cwiseAbs().maxCoeff(), 1e-13 * 6.25);
      EXPECT_NEAR(k.js, l1 * l2, 1e-13 * l1 * l2);
      EXPECT_NEAR(k.i1, l1 * l1 + l2 * l2 - 2.0, 1e-13 * 12.5);
      EXPECT_LT((k.A * k.A.transpose() - B).cwiseAbs().maxCoeff(), 1e-13 * 6.25);
      EXPECT_LT((k.A * s.P_ref - k.A).cwiseAbs().maxCoeff(), 1e-13 * 2.5);
      // Principal decomposition (sorted) recovers stretches, tensions and directions.
      const PointPrincipal p = point_principal(*law, k);
      EXPECT_NEAR(p.lambda1, std::max(l1, l2), 1e-12);
      EXPECT_NEAR(p.lambda2, std::min(l1, l2), 1e-12);
      EXPECT_NEAR(p.tension1, std::max(p1, p2), 1e-12 * scale);
      EXPECT_NEAR(p.tension2, std::min(p1, p2), 1e-12 * scale);
      if (std::abs(l1 - l2) > 0.05) {
        const Vector3d dmax = l1 > l2 ? s.d1 : s.d2;
        EXPECT_NEAR(std::abs(p.stretch_dir1.dot(dmax)), 1.0, 1e-10);
        EXPECT_NEAR(p.tension_dir1.dot(tau * p.tension_dir1), p.tension1, 1e-11 * scale);
      }
    }
  }
  std::printf("max relative |tau_cartesian - tau_principal| over all laws: %.2e\n", worst);
}

TEST(MembraneLaw, EqualStretchesNeedNoEigenDecomposition) {
  // l1 = l2: tau = tau0 P exactly, and the principal output is still finite and consistent.
  std::mt19937 gen(7);
  for (const auto& law : all_laws()) {
    const Sample s = make_sample(gen, 1.3, 1.3);
    const PointKinematics k = point_kinematics(s.T1, s.T2, s.t1, s.t2);
    const double t0 = law->principal_tension(1.3, 1.3);
    EXPECT_LT((tension_tensor(*law, k) - t0 * k.P).cwiseAbs().maxCoeff(), 1e-12 * std::abs(t0));
    const PointPrincipal p = point_principal(*law, k);
    EXPECT_NEAR(p.tension1, t0, 1e-12 * std::abs(t0));
    EXPECT_NEAR(p.tension2, t0, 1e-12 * std::abs(t0));
    EXPECT_NEAR(p.stretch_dir1.norm(), 1.0, 1e-14);
  }
}

TEST(MembraneLaw, PrincipalTensionIsEnergyDerivative) {
  // tau_1 = (1/l2) dw/dl1 (w per reference area) by central differences.
  for (const auto& law : all_laws()) {
    for (double l1 : {0.6, 1.0, 1.7, 2.4})
      for (double l2 : {0.7, 1.2, 2.0}) {
        auto w = [&](double a, double b) {
          return law->energy(a * a + b * b - 2.0, a * a * b * b - 1.0).w;
        };
        const double h = 1e-5;
        const double fd = (w(l1 + h, l2) - w(l1 - h, l2)) / (2 * h) / l2;
        const double t1 = law->principal_tension(l1, l2);
        EXPECT_NEAR(fd, t1, 1e-8 * std::max(1.0, std::abs(t1))) << label(*law) << l1 << " " << l2;
      }
    // Stress-free, energy-free reference state.
    EXPECT_NEAR(law->energy(0.0, 0.0).w, 0.0, 1e-15) << label(*law);
    EXPECT_NEAR(law->principal_tension(1.0, 1.0), 0.0, 1e-15) << label(*law);
  }
}

TEST(MembraneLaw, UniaxialStretch) {
  for (double l1 : {1.05, 1.3, 1.8, 2.5, 3.5}) {
    // neo-Hookean and Mooney-Rivlin: tau2 = 0 at l2 = l1^-1/2.
    const double l2 = 1.0 / std::sqrt(l1);
    const NeoHookeanLaw nh;
    const double nh_exact = std::pow(l1, 1.5) - std::pow(l1, -1.5);
    for (double psi : {0.0, 0.4, 1.0}) {
      const MooneyRivlinLaw mr(psi);
      std::mt19937 gen(11);
      const Sample s = make_sample(gen, l1, l2);
      const PointKinematics k = point_kinematics(s.T1, s.T2, s.t1, s.t2);
      const Eigen::Matrix3d tau = tension_tensor(mr, k);
      const double t1 = nh_exact * (psi + (1.0 - psi) / l1);
      EXPECT_NEAR(s.d2.dot(tau * s.d2), 0.0, 1e-13 * t1) << "MR psi=" << psi;
      EXPECT_NEAR(s.d1.dot(tau * s.d1), t1, 1e-13 * t1) << "MR psi=" << psi;
      if (psi == 1.0) {
        const Eigen::Matrix3d tn = tension_tensor(nh, k);
        EXPECT_NEAR(s.d1.dot(tn * s.d1), nh_exact, 1e-13 * nh_exact);
        EXPECT_NEAR(s.d2.dot(tn * s.d2), 0.0, 1e-13 * nh_exact);
      }
    }
    // Skalak: tau2 = 0 at l2^2 = (1 + C l1^2)/(1 + C l1^4).
    for (double c : {0.5, 1.0, 10.0}) {
      const SkalakLaw sk(c);
      const double m2 = std::sqrt((1 + c * l1 * l1) / (1 + c * l1 * l1 * l1 * l1));
      std::mt19937 gen(12);
      const Sample s = make_sample(gen, l1, m2);
      const PointKinematics k = point_kinematics(s.T1, s.T2, s.t1, s.t2);
      const Eigen::Matrix3d tau = tension_tensor(sk, k);
      const double t1 = sk.principal_tension(l1, m2);
      EXPECT_GT(t1, 0.0);
      EXPECT_NEAR(s.d2.dot(tau * s.d2), 0.0, 1e-13 * t1) << "Skalak C=" << c << " l1=" << l1;
      EXPECT_NEAR(s.d1.dot(tau * s.d1), t1, 1e-13 * t1);
    }
  }
}

TEST(MembraneLaw, SmallStrainModuli) {
  // Gs: pure shear l = (1+e, 1-e): tau1 - tau2 = 4 Gs e.  Ks: isotropic l = sqrt(Js):
  // tau = Ks (Js - 1) to first order. Central differences, h = 1e-5.
  const double h = 1e-5;
  struct Case {
    std::shared_ptr<const Law> law;
    double ks;
  };
  for (const Case& c :
       {Case{std::make_shared<NeoHookeanLaw>(), 3.0}, Case{std::make_shared<SkalakLaw>(1.0), 3.0},
        Case{std::make_shared<SkalakLaw>(0.3), 1.6}, Case{std::make_shared<SkalakLaw>(10.0), 21.0},
        Case{std::make_shared<MooneyRivlinLaw>(0.0), 3.0},
        Case{std::make_shared<MooneyRivlinLaw>(0.5), 3.0},
        Case{std::make_shared<NeoHookeanLaw>(2.5), 7.5}}) {
    const Law& L = *c.law;
    auto shear = [&](double e) {
      return L.principal_tension(1 + e, 1 - e) - L.principal_tension(1 - e, 1 + e);
    };
    const double gs = (shear(h) - shear(-h)) / (2 * h) / 4.0;
    auto iso = [&](double j) { return L.principal_tension(std::sqrt(j), std::sqrt(j)); };
    const double ks = (iso(1 + h) - iso(1 - h)) / (2 * h);
    EXPECT_NEAR(gs, L.gs(), 1e-8) << label(L);
    EXPECT_NEAR(ks, c.ks, 1e-8 * c.ks) << label(L);
  }
}

TEST(MembraneLaw, OptionsValidationAndFactory) {
  std::string err;
  LawOptions o;
  EXPECT_TRUE(o.IsValid(&err));
  o.kind = LawKind::Skalak;
  o.c = -0.6;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("Skalak"), std::string::npos);
  EXPECT_THROW(make_law(o), std::invalid_argument);
  o.kind = LawKind::MooneyRivlin;
  o.psi = 1.2;
  EXPECT_FALSE(o.IsValid(&err));
  o.psi = 0.3;
  o.gs = 2.0;
  auto law = make_law(o);
  EXPECT_EQ(law->name(), "mooney-rivlin");
  EXPECT_DOUBLE_EQ(law->principal_tension(1.2, 0.9),
                   2.0 * MooneyRivlinLaw(0.3).principal_tension(1.2, 0.9));
  o.gs = 0.0;
  EXPECT_FALSE(o.IsValid(&err));
  LawKind kind;
  EXPECT_TRUE(parse_law_kind("neo-hookean", &kind));
  EXPECT_EQ(kind, LawKind::NeoHookean);
  EXPECT_EQ(to_string(kind), "neo-hookean");
  EXPECT_FALSE(parse_law_kind("hooke", &kind));
}

}  // namespace
}  // namespace capflow::membrane
