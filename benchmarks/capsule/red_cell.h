// The red blood cell the capsule benchmarks and studies share: the Evans-Fung cell with its axis
// along the flow, a Skalak membrane with C = 10, bending Eb = 5e-3 about its own shape, in
// simple shear.
#pragma once

#include "capsule/capsule.h"

namespace capflow::bench {

inline capsule::DynamicsOptions red_cell_dynamics() {
  capsule::DynamicsOptions o;
  o.shape.kind = geometry::ReferenceShape::Kind::Biconcave;
  o.shape.axis = 0;
  o.bending.modulus = 5e-3;
  o.bending.model = membrane::BendingModel::Reference;
  return o;
}

// The cell on `mesh`, advanced from rest by `steps` RK4 steps of `dt` at capillary number `ca`.
inline capsule::Capsule red_cell(const geometry::Mesh& mesh, int steps, double dt, double ca) {
  membrane::LawOptions law;
  law.c = 10;
  capsule::Capsule cap(mesh, law, capsule::Flow::simple_shear(), red_cell_dynamics());
  for (int k = 0; k < steps; ++k) cap.step(dt, [ca](double) { return ca; });
  return cap;
}

}  // namespace capflow::bench
