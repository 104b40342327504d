// Capsule dynamics: symmetry reduction equals the full evaluation; flows; rigid-body and
// steady-state sanity; health monitor triggers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "../membrane/membrane_test_util.h"
#include "capsule/capsule.h"
#include "capsule/health.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"
#include "spectral/spectral.h"

using namespace capflow;
using namespace capflow::capsule;

namespace {
// A deformed state with the symmetries of the flow (a smooth map of the sphere).
Eigen::Matrix3Xd deformed(const geometry::Mesh& mesh, bool shear) {
  return geometry::map_points(
      mesh.reference(), [shear](const Eigen::Vector3d& p) -> Eigen::Vector3d {
        if (!shear) return {1.2 * p.x() * (1 + 0.1 * p.y() * p.y()), 0.85 * p.y(), 1.02 * p.z()};
        // Tilted ellipsoid in the x-z plane: symmetric under y -> -y and (x,z) -> (-x,-z).
        const double c = std::cos(0.4), s = std::sin(0.4);
        const Eigen::Vector3d q(1.3 * p.x(), 0.95 * p.y(), 0.8 * p.z());
        return {c * q.x() - s * q.z(), q.y(), s * q.x() + c * q.z()};
      });
}
}  // namespace

TEST(Capsule, OctantSymmetryEqualsFullEvaluation) {
  for (int ne : {6, 10}) {
    const geometry::Mesh mesh(ne, 8);
    Capsule cap(mesh, membrane::LawOptions{}, Flow::planar_extension());
    EXPECT_EQ(cap.symmetry().kind(), SymmetryKind::Octant);
    const Eigen::Matrix3Xd x = deformed(mesh, false);
    const Eigen::Matrix3Xd u = cap.velocity(x, 0.3), uf = cap.velocity_full(x, 0.3);
    EXPECT_LT((u - uf).cwiseAbs().maxCoeff(), 1e-10) << ne;
    EXPECT_LT(cap.symmetry().targets().size() * 6, static_cast<size_t>(mesh.num_unique()));
  }
}

TEST(Capsule, ShearSymmetryEqualsFullEvaluation) {
  const geometry::Mesh mesh(14, 8);
  DynamicsOptions opt;
  Capsule cap(mesh, membrane::LawOptions{membrane::LawKind::NeoHookean}, Flow::simple_shear(), opt);
  EXPECT_EQ(cap.symmetry().kind(), SymmetryKind::Shear);
  const Eigen::Matrix3Xd x = deformed(mesh, true);
  const Eigen::Matrix3Xd u = cap.velocity(x, 0.2), uf = cap.velocity_full(x, 0.2);
  EXPECT_LT((u - uf).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(cap.symmetry().targets().size() * 3, static_cast<size_t>(mesh.num_unique()));
}

TEST(Capsule, CustomGradientsGetTheSymmetryTheyHave) {
  // Uniaxial extension along x (diagonal): octant; a shear-plus-extension in the x-z plane (y
  // decoupled): the shear pair; a gradient coupling y: none. Each reduced evaluation equals
  // the full one on a state with that symmetry.
  const geometry::Mesh mesh(6, 8);
  Eigen::Matrix3d uni = Eigen::Vector3d(1, -0.5, -0.5).asDiagonal();
  Eigen::Matrix3d xz = Eigen::Matrix3d::Zero();
  xz(0, 2) = 1;
  xz(0, 0) = 0.3;
  xz(2, 2) = -0.3;
  Eigen::Matrix3d coupled = Eigen::Matrix3d::Zero();
  coupled(0, 1) = 1;
  const struct {
    Eigen::Matrix3d g;
    SymmetryKind kind;
    bool shear_state;
  } cases[] = {{uni, SymmetryKind::Octant, false},
               {xz, SymmetryKind::Shear, true},
               {coupled, SymmetryKind::None, true}};
  for (const auto& c : cases) {
    Capsule cap(mesh, membrane::LawOptions{}, Flow::custom(c.g));
    EXPECT_EQ(cap.symmetry().kind(), c.kind);
    const Eigen::Matrix3Xd x = deformed(mesh, c.shear_state);
    const Eigen::Matrix3Xd u = cap.velocity(x, 0.3), uf = cap.velocity_full(x, 0.3);
    EXPECT_LT((u - uf).cwiseAbs().maxCoeff(), 1e-10);
  }
}

TEST(Capsule, RestingSphereMovesWithTheFlow) {
  // The undeformed sphere carries no tension: u = u_inf exactly (up to round-off of f).
  const geometry::Mesh mesh(6, 8);
  Capsule cap(mesh, membrane::LawOptions{}, Flow::planar_extension());
  const Eigen::Matrix3Xd u = cap.velocity(mesh.reference(), 0.5);
  const Eigen::Matrix3Xd expect = Flow::planar_extension().gradient * mesh.reference();
  EXPECT_LT((u - expect).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(Capsule, InflatedSphereIsInEquilibrium) {
  // An isotropically inflated sphere carries a uniform normal load f = (2 tau0/alpha) n, which a
  // Stokes flow balances by a pressure jump: u = 0 (INT S.n dS = 0 on any closed surface).
  const geometry::Mesh mesh(6, 10);
  Capsule cap(mesh, membrane::LawOptions{}, Flow::custom(Eigen::Matrix3d::Zero()));
  const Eigen::Matrix3Xd x = 1.1 * mesh.reference();
  const double fscale = cap.traction(x).colwise().norm().maxCoeff() * 1.1 * 2.0 / 3.0;
  EXPECT_GT(fscale, 0.1);
  const Eigen::Matrix3Xd u = cap.velocity(x, 1.0);
  EXPECT_LT(u.cwiseAbs().maxCoeff(), 1e-4 * fscale);
}

TEST(Capsule, RefusesViscosityRatiosOutsideTheRange) {
  const geometry::Mesh mesh(6, 6);
  for (double bad : {0.0, -1.0, 150.0}) {
    DynamicsOptions opt;
    opt.viscosity_ratio = bad;
    try {
      Capsule cap(mesh, membrane::LawOptions{}, Flow::planar_extension(), opt);
      FAIL() << "expected std::invalid_argument for " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("(0, 100]"), std::string::npos) << e.what();
    }
  }
}

TEST(Capsule, RestingSphereWithAViscosityRatioMovesAtFiveOverTwoLambdaPlusThree) {
  // The unstressed sphere with inner viscosity lambda in a pure strain: u = 5 / (2 lambda + 3)
  // u_inf (capsule/viscosity_ratio.h), with the symmetry targets and with every node.
  const geometry::Mesh mesh(6, 10);
  const Eigen::Matrix3Xd u_inf = Flow::planar_extension().gradient * mesh.reference();
  for (double lambda : {0.2, 5.0}) {
    DynamicsOptions opt;
    opt.viscosity_ratio = lambda;
    Capsule cap(mesh, membrane::LawOptions{}, Flow::planar_extension(), opt);
    const double a = 5.0 / (2.0 * lambda + 3.0);
    EXPECT_LT((cap.velocity(mesh.reference(), 0.5) - a * u_inf).cwiseAbs().maxCoeff(), 2e-6);
    EXPECT_LT((cap.velocity_full(mesh.reference(), 0.5) - a * u_inf).cwiseAbs().maxCoeff(), 2e-6);
    EXPECT_GT(cap.krylov_iterations(), 0);
  }
}

TEST(Capsule, RestingSphereInShearWithAViscosityRatioTurnsRigidlyAndStrainsLess) {
  // Simple shear u_inf = G x is a strain E = (G + G^T)/2 plus a rotation W = (G - G^T)/2: the
  // rotation is a rigid-body motion, which the double layer leaves alone, so the unstressed
  // sphere moves with u = 5 / (2 lambda + 3) E x + W x (shear symmetry targets: y >= 0, x >= 0).
  const geometry::Mesh mesh(6, 10);
  const Eigen::Matrix3d G = Flow::simple_shear().gradient;
  const Eigen::Matrix3d E = 0.5 * (G + G.transpose()), W = 0.5 * (G - G.transpose());
  for (double lambda : {0.2, 5.0}) {
    DynamicsOptions opt;
    opt.viscosity_ratio = lambda;
    Capsule cap(mesh, membrane::LawOptions{}, Flow::simple_shear(), opt);
    const Eigen::Matrix3Xd expect = (5.0 / (2.0 * lambda + 3.0) * E + W) * mesh.reference();
    EXPECT_LT((cap.velocity(mesh.reference(), 0.3) - expect).cwiseAbs().maxCoeff(), 2e-6)
        << "lambda " << lambda;
  }
}

TEST(Capsule, QuadratureScaleRaisesEveryOrderAndKeepsTheVelocity) {
  // Doubling every quadrature order is an accuracy check: the orders double (rounded) and the
  // velocity at a smooth deformed state stays within the default rules' accuracy (~1e-8).
  const geometry::Mesh mesh(6, 8);
  const Capsule base(mesh, membrane::LawOptions{}, Flow::planar_extension());
  DynamicsOptions opt;
  opt.quadrature_scale = 2.0;
  const Capsule fine(mesh, membrane::LawOptions{}, Flow::planar_extension(), opt);
  const stokes::QuadratureOptions& q1 = base.quadrature();
  const stokes::QuadratureOptions& q2 = fine.quadrature();
  EXPECT_EQ(q2.nq_far, 2 * q1.nq_far);
  EXPECT_EQ(q2.nq_mid, 2 * q1.nq_mid);
  EXPECT_EQ(q2.n_edge, 2 * q1.n_edge);
  EXPECT_EQ(q2.n_radial, 2 * q1.n_radial);
  EXPECT_EQ(q2.n_radial_inner, 2 * q1.n_radial_inner);
  EXPECT_EQ(q2.n_edge_near, 2 * q1.n_edge_near);
  EXPECT_EQ(q2.n_radial_near, 2 * q1.n_radial_near);
  EXPECT_EQ(q2.n_radial_near_out, 2 * q1.n_radial_near_out);
  const Eigen::Matrix3Xd x = deformed(mesh, false);
  const Eigen::Matrix3Xd u1 = base.velocity(x, 0.3), u2 = fine.velocity(x, 0.3);
  const Eigen::Matrix3Xd ui = Flow::planar_extension().gradient * x;
  const double du = (u1 - u2).cwiseAbs().maxCoeff(), scale = (u1 - ui).cwiseAbs().maxCoeff();
  EXPECT_GT(scale, 0.05);
  EXPECT_GT(du, 0.0);  // the rules did change
  EXPECT_LT(du, 1e-6 * scale);
  opt.quadrature_scale = 0.5;
  EXPECT_THROW(Capsule(mesh, membrane::LawOptions{}, Flow::planar_extension(), opt),
               std::invalid_argument);
}

TEST(Capsule, VolumeCorrectionRestoresVolume) {
  const geometry::Mesh mesh(6, 8);
  DynamicsOptions opt;
  opt.volume_correction = true;
  Capsule cap(mesh, membrane::LawOptions{}, Flow::planar_extension(), opt);
  cap.set_state(1.01 * mesh.reference(), 0.0, 0);  // 3% too much volume
  cap.step(1e-3, [](double) { return 0.4; });
  EXPECT_NEAR(enclosed_volume(mesh, cap.positions()) / cap.initial_volume(), 1.0, 1e-12);
}

TEST(Health, DetectsNanJacobianFlipAndOscillation) {
  const geometry::Mesh mesh(6, 8);
  HealthMonitor hm(mesh, mesh.reference());
  EXPECT_EQ(hm.check(mesh.reference(), 0.0).level, HealthLevel::Ok);
  Eigen::Matrix3Xd x = mesh.reference();
  x(1, 17) = std::nan("");
  HealthReport r = hm.check(x, 0.1);
  EXPECT_EQ(r.level, HealthLevel::Failure);
  EXPECT_EQ(r.cause, "nan");
  // named by the node and where it was in the last good state (here the sphere)
  EXPECT_NE(r.message.find("element 0, node (1, 2), last good position ("), std::string::npos)
      << r.message;
  EXPECT_EQ(r.message.find("nan"), std::string::npos) << r.message;
  // Inverting the surface flips every Jacobian.
  r = hm.check(geometry::map_points(mesh.reference(),
                                    [](const Eigen::Vector3d& p) -> Eigen::Vector3d {
                                      return {-p.x(), p.y(), p.z()};
                                    }),
               0.2);
  EXPECT_EQ(r.cause, "jacobian");
  EXPECT_NE(r.message.find("t = 0.2"), std::string::npos);
  EXPECT_NE(r.message.find("last good position"), std::string::npos);
  // A small sawtooth on the interior nodes of one element (a fresh monitor: the last good
  // state above is the sphere).
  HealthOptions opt;
  opt.oscillation_warn = 2e-4;
  opt.oscillation_fail = 1e-3;
  HealthMonitor hm2(mesh, mesh.reference(), opt);
  EXPECT_LT(hm2.oscillation_indicator(mesh.reference()), 1e-4);
  x = mesh.reference();
  for (int j = 1; j < 7; ++j)
    for (int i = 1; i < 7; ++i) x.col(mesh.local(4, i, j)) *= 1.0 + 0.005 * ((i % 2) ? 1 : -1);
  r = hm2.check(x, 0.3);
  EXPECT_EQ(r.cause, "oscillation");
  EXPECT_EQ(r.level, HealthLevel::Failure);
  EXPECT_NE(r.message.find("oscillation"), std::string::npos);
}

// On the unit sphere the normal is the position, so the turning between neighbouring nodes is
// their central angle (to the interpolation error of the normal); a thin ellipsoid's tips
// (radius b^2/a) turn it by more than the warning angle at small NB: one warning, then none.
TEST(Health, ResolutionWarningWhenTheNormalTurnsTooFastBetweenNodes) {
  const geometry::Mesh mesh(6, 10);
  HealthMonitor hm(mesh, mesh.reference());
  const Eigen::Matrix3Xd& s = mesh.reference();
  double central = 0;
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i + 1 < 10; ++i)
        for (int dir = 0; dir < 2; ++dir) {
          const Eigen::Vector3d a = s.col(dir ? mesh.local(e, j, i) : mesh.local(e, i, j));
          const Eigen::Vector3d b = s.col(dir ? mesh.local(e, j, i + 1) : mesh.local(e, i + 1, j));
          central = std::max(central, std::atan2(a.cross(b).norm(), a.dot(b)));
        }
  const geometry::SurfaceGeometry g = geometry::compute_geometry(mesh, s);
  EXPECT_NEAR(geometry::max_normal_turning(mesh, g.n), central, 1e-5);
  EXPECT_LT(central, 0.3);
  EXPECT_EQ(hm.check(s, 0.0).level, HealthLevel::Ok);

  const geometry::Mesh coarse(6, 6);
  const Eigen::Matrix3Xd thin =
      geometry::map_points(coarse.reference(), geometry::ellipsoid_map(3.0, 0.3, 1.0));
  HealthOptions opt;
  opt.oscillation_warn = 1.0;  // this check only
  opt.oscillation_fail = 2.0;
  HealthMonitor hm2(coarse, thin, opt);
  int node = -1;
  const double turn =
      geometry::max_normal_turning(coarse, geometry::compute_geometry(coarse, thin).n, &node);
  EXPECT_GT(turn, opt.resolution_warn_angle);
  EXPECT_GT(std::abs(thin(0, node)), 2.0);  // at a tip
  HealthReport r = hm2.check(thin, 1.5);
  EXPECT_EQ(r.level, HealthLevel::Warning);
  EXPECT_EQ(r.cause, "resolution");
  EXPECT_NE(r.message.find("t = 1.5"), std::string::npos);
  EXPECT_NE(r.message.find("mesh.nb"), std::string::npos);
  EXPECT_EQ(hm2.check(thin, 1.6).level, HealthLevel::Ok);  // once
  // checkpoint flags: the warned state survives; 3-value flags of older checkpoints load
  HealthMonitor hm3(coarse, thin, opt);
  hm3.restore(hm2.normals(), hm2.flags());
  EXPECT_EQ(hm3.check(thin, 1.7).level, HealthLevel::Ok);
  hm3.restore(hm2.normals(), {0.0, 0.0, -1.0});
  EXPECT_EQ(hm3.check(thin, 1.8).cause, "resolution");
  EXPECT_THROW(hm3.restore(hm2.normals(), {0.0, 0.0}), std::invalid_argument);
}

TEST(Health, WrinklingWarningNeedsPersistenceNearSteadyState) {
  const geometry::Mesh mesh(6, 6);
  HealthMonitor hm(mesh, mesh.reference());
  const Eigen::Vector3d at(0, 0, 1);
  EXPECT_EQ(hm.check_wrinkling(0.0, -0.1, at, 0.5).level, HealthLevel::Ok);   // not steady
  EXPECT_EQ(hm.check_wrinkling(1.0, -0.1, at, 1e-5).level, HealthLevel::Ok);  // starts
  const HealthReport r = hm.check_wrinkling(2.5, -0.1, at, 1e-5);
  EXPECT_EQ(r.level, HealthLevel::Warning);
  EXPECT_EQ(r.cause, "wrinkling");
}

TEST(Capsule, MembraneLoadIsForceAndTorqueFreeWithTheSmoothedTangents) {
  // With the tangents the dynamics uses (edge tensors A averaged over coincident nodes, paper
  // eqs. 18-19), the two elements sharing an edge see the same tension and conormal there, so
  // the conservative form telescopes: INT f dS vanishes to round-off on ANY shape, not only on
  // mirror-symmetric ones (with each element's own Lagrange tangents it is only exponentially
  // small: tests/membrane, MembraneValidation.ForceAndTorqueBalanceConvergeInNB).
  const geometry::PointMap skew = membrane::testing::skew_map();
  for (int ne : {6, 10, 14})
    for (const membrane::LawKind kind : {membrane::LawKind::Skalak, membrane::LawKind::NeoHookean,
                                         membrane::LawKind::MooneyRivlin}) {
      const geometry::Mesh mesh(ne, 12);
      membrane::LawOptions law;
      law.kind = kind;
      law.psi = 0.5;
      const Capsule cap(mesh, law, Flow::planar_extension());
      const Eigen::Matrix3Xd x = geometry::map_points(mesh.reference(), skew);
      Eigen::Matrix3Xd t1, t2, f;
      cap.tangents(x, &t1, &t2);
      cap.membrane().traction_from_tangents(t1, t2, &f);
      // Nodal (Gauss-Lobatto) quadrature with the same area element the load formula uses.
      const Eigen::VectorXd w1 = spectral::gauss_lobatto(mesh.nb()).w;
      Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
      double total = 0;
      for (int e = 0; e < mesh.ne(); ++e)
        for (int j = 0; j < mesh.nb(); ++j)
          for (int i = 0; i < mesh.nb(); ++i) {
            const int m = mesh.local(e, i, j);
            const double w = w1[i] * w1[j] * t1.col(m).cross(t2.col(m)).norm();
            force += w * f.col(m);
            torque += w * x.col(m).cross(f.col(m));
            total += w * f.col(m).norm();
          }
      std::printf("NE=%d law %d: |INT f dS| / INT |f| dS = %.1e, torque %.1e\n", ne,
                  static_cast<int>(kind), force.norm() / total, torque.norm() / total);
      EXPECT_LT(force.norm(), 1e-12 * total) << "NE=" << ne;
      EXPECT_LT(torque.norm(), 1e-11 * total) << "NE=" << ne;
    }
}

// The steady solver's step map (capsule/steady_solver.h): one explicit midpoint step has a local
// error O(dt^3) against the exact flow of the node velocities (here: RK4 with 16 substeps), so
// halving dt divides the error by ~8; and it is second-order consistent with the RK4 step.
TEST(Capsule, MidpointStepHasThirdOrderLocalError) {
  const geometry::Mesh mesh(6, 8);
  DynamicsOptions opt;
  opt.smooth_geometry = false;  // the plain Runge-Kutta maps
  opt.volume_correction = false;
  const Capsule cap(mesh, membrane::LawOptions{}, Flow::planar_extension(), opt);
  const Eigen::Matrix3Xd x = deformed(mesh, false);
  const double ca = 0.3;
  auto reference = [&](double dt) {
    Eigen::Matrix3Xd y = x;
    for (int k = 0; k < 16; ++k) y = cap.rk4_step(y, 0.0, dt / 16, [ca](double) { return ca; });
    return y;
  };
  double err[3];
  const double dts[3] = {0.02, 0.01, 0.005};
  for (int i = 0; i < 3; ++i)
    err[i] = (cap.midpoint_step(x, dts[i], ca) - reference(dts[i])).cwiseAbs().maxCoeff();
  std::printf("midpoint local error: %.3e %.3e %.3e (ratios %.2f %.2f)\n", err[0], err[1], err[2],
              err[0] / err[1], err[1] / err[2]);
  EXPECT_GT(err[2], 1e-13);  // above rounding: the rates below measure the method
  EXPECT_NEAR(err[0] / err[1], 8.0, 1.2);
  EXPECT_NEAR(err[1] / err[2], 8.0, 1.2);
}

TEST(Flow, DescriptionsMatchTheVelocityGradient) {
  // The frames' text block reads the flow off its gradient: the shear's description names the
  // axis and sign of the curl of u (central differences of velocity()) and u_x = G z.
  const Flow shear = Flow::simple_shear();
  Eigen::Vector3d curl;
  const double h = 1e-3;
  auto du = [&](int comp, int axis) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(axis);
    return (shear.velocity(e)[comp] - shear.velocity(-e)[comp]) / (2 * h);
  };
  curl << du(2, 1) - du(1, 2), du(0, 2) - du(2, 0), du(1, 0) - du(0, 1);
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(curl[a]) > std::abs(curl[axis])) axis = a;
  const std::string named = std::string(curl[axis] > 0 ? "+" : "\u2212") + "xyz"[axis];
  EXPECT_NEAR(curl.norm(), 1, 1e-12);
  EXPECT_NE(shear.description().find("vorticity along " + named + ")"), std::string::npos)
      << shear.description() << " (curl along " << named << ")";
  EXPECT_NEAR(shear.velocity(Eigen::Vector3d(0, 0, 2))[0], 2, 1e-15);  // u_x = G z
  EXPECT_EQ(shear.description(), "simple shear (u = G z along x, vorticity along +y)");
  EXPECT_EQ(Flow::planar_extension().description(),
            "planar extension (stretching along x, compressing along y)");
  EXPECT_EQ(Flow::custom(Eigen::Matrix3d::Zero()).description(), "custom velocity gradient");
}

namespace capflow::capsule {
namespace {

// Milestone 15: a capsule of another reference shape starts stress-free at that shape - with the
// reference bending model, bending-free too - so it moves with the flow; Helfrich bending loads it.
TEST(Capsule, ReferenceShapesStartStressFree) {
  const geometry::Mesh mesh(6, 10);
  geometry::ReferenceShape rbc;
  rbc.kind = geometry::ReferenceShape::Kind::Biconcave;
  rbc.axis = 0;
  geometry::ReferenceShape prolate;
  prolate.kind = geometry::ReferenceShape::Kind::Spheroid;
  prolate.aspect = 2;
  for (const geometry::ReferenceShape& s : {rbc, prolate}) {
    DynamicsOptions o;
    o.shape = s;
    o.bending.modulus = 0.005;
    o.bending.model = membrane::BendingModel::Reference;
    Capsule cap(mesh, membrane::LawOptions{}, Flow::simple_shear(), o);
    const Eigen::Matrix3Xd x0 = geometry::reference_positions(mesh, s);
    EXPECT_EQ((cap.positions() - x0).cwiseAbs().maxCoeff(), 0.0) << "the initial shape";
    EXPECT_NEAR(cap.initial_volume(), 4 * M_PI / 3, 1e-6) << "equal-volume radius 1";
    EXPECT_LT(cap.traction(x0).cwiseAbs().maxCoeff(), 1e-9);
    const Eigen::Matrix3Xd u = cap.velocity(x0, 0.1);
    EXPECT_LT((u - Flow::simple_shear().gradient * x0).cwiseAbs().maxCoeff(), 1e-9);
    // Helfrich bending (c0 = 0) loads the same shape.
    o.bending.model = membrane::BendingModel::Helfrich;
    Capsule bent(mesh, membrane::LawOptions{}, Flow::simple_shear(), o);
    EXPECT_GT(bent.traction(x0).cwiseAbs().maxCoeff(), 1e-3);
  }
}

}  // namespace
}  // namespace capflow::capsule
