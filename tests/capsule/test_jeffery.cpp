// The rigid-particle limit: an oblate spheroidal capsule (aspect r = 0.5, symmetry axis along the
// flow, Skalak C = 1 with bending Eb = 0.01 about its own shape) is stiff at small Ca: its
// membrane cannot tank-tread, so it tumbles in simple shear like a rigid spheroid, with
// Jeffery's period T G = 2 pi (r + 1/r); the shape repeats every T/2 = pi (r + 1/r) = 7.854.
// Measured: the time between two downward crossings of 45 degrees by the inclination of the
// in-plane long axis (the first at t ~ 1.15, after the start), RK4 steps of dt = 0.004.
// At NE = 6: +0.81 % at NB = 6, +0.28 % at NB = 8 (Ca = 0.025, by capflow run's adaptive steps);
// Ca = 0.05 / 0.025 / 0.0125 give +1.27 / +0.81 / +0.69 % at NB = 6 (docs/validation.md, 19.5).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "capsule/capsule.h"
#include "diagnostics/diagnostics.h"

namespace capflow::capsule {
namespace {

TEST(Jeffery, AStiffOblateCapsuleTumblesWithJefferysPeriod) {
  const geometry::Mesh mesh(6, 6);
  DynamicsOptions o;
  o.shape.kind = geometry::ReferenceShape::Kind::Spheroid;
  o.shape.aspect = 0.5;
  o.shape.axis = 0;
  o.bending.modulus = 0.01;
  o.bending.model = membrane::BendingModel::Reference;
  membrane::LawOptions law;
  law.c = 1;
  Capsule cap(mesh, law, Flow::simple_shear(), o);
  diagnostics::ShapeOptions so;
  so.axes = diagnostics::AxesMode::Shear;
  so.extrema = false;
  so.edge_curvature = false;
  const auto inclination = [&] {
    return diagnostics::measure_shape(mesh, cap.positions(), so).inclination_deg;
  };
  const CaFunction ca = [](double) { return 0.025; };
  const double dt = 0.004, level = 45;
  std::vector<double> crossings;
  double previous = inclination(), t_previous = 0;
  while (crossings.size() < 2 && cap.time() < 12) {
    cap.step(dt, ca);
    const double now = inclination();
    // a downward crossing of the level (the wrap from -90 to +90 is no crossing)
    if (previous > level && now <= level && previous - now < 90)
      crossings.push_back(t_previous + (previous - level) / (previous - now) * dt);
    previous = now;
    t_previous = cap.time();
  }
  ASSERT_EQ(crossings.size(), 2u) << "no tumbling by t = " << cap.time();
  const double half_period = crossings[1] - crossings[0];
  const double jeffery = M_PI * (0.5 + 1 / 0.5);
  std::printf("T G / 2 = %.4f (crossings at %.4f, %.4f), Jeffery %.4f, relative difference %+.2e\n",
              half_period, crossings[0], crossings[1], jeffery, half_period / jeffery - 1);
  EXPECT_NEAR(half_period / jeffery, 1, 0.02);
}

}  // namespace
}  // namespace capflow::capsule
