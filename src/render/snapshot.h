// capflow/render/snapshot: the ONLY data that crosses from the simulation thread to the
// renderer thread. Plain, copyable, self-contained (std::vector/std::string only): no solver
// pointers, no Eigen, no GL. The producer fills a fresh Snapshot and hands it over by value;
// the queue owns it from then on.
//
// Layout (the solver's element-local node order):
//   node k = (e*nb + j)*nb + i, e in [0, ne), i (along xi) and j (along eta) in [0, nb),
//   at the Gauss-Lobatto points of [-1,1]^2 (spectral::gauss_lobatto(nb)); nodes on element
//   edges appear once per element that holds them. x[3k+0..2] = position of node k.
//   tau1[k] >= tau2[k]: principal tensions (units of the solver's tension scale, G_s) at node
//   k; both empty when not available (the renderer then colours by tau = 0).
#pragma once

#include <string>
#include <vector>

namespace capflow::render {

struct SnapshotDiagnostics {
  double D = 0;        // Taylor deformation (L - B) / (L + B)
  double L = 0;        // half-length of the inertia ellipsoid (longest semi-axis)
  double S = 0;        // shortest semi-axis in the shear plane
  double W = 0;        // semi-axis along the vorticity axis
  double tau_max = 0;  // max over the surface of tau1
  double tau_min = 0;  // min over the surface of tau2
};

struct Snapshot {
  int ne = 0;                // number of elements (6, 10, 14)
  int nb = 0;                // Gauss-Lobatto nodes per element direction
  std::vector<double> x;     // 3 * ne*nb*nb node positions
  std::vector<double> tau1;  // ne*nb*nb (or empty)
  std::vector<double> tau2;  // ne*nb*nb (or empty)
  std::vector<double> curvature;  // mean curvature H at the nodes, ne*nb*nb (or empty)
  std::vector<double> speed;      // |dx/dt| at the nodes, ne*nb*nb (or empty)
  std::vector<double> bending;    // bending energy density (kappa_b / 2)(2H - c0)^2 (Gs) at the
                                  // nodes, ne*nb*nb (or empty: no bending)
  double time = 0;           // simulated time (units of 1/shear rate)
  double ca = 0;             // capillary number
  std::string law;           // membrane law name, e.g. "neo-Hookean"
  std::string flow;          // the flow and its principal directions, for the text block
                             // (empty: not shown)
  SnapshotDiagnostics diag;
  long frame = -1;  // movie frame index set by the producer (-1: not a movie frame)

  int num_nodes() const { return ne * nb * nb; }
  // Sizes consistent and ne, nb positive; on failure *error says what is wrong.
  bool IsValid(std::string* error) const {
    auto fail = [&](const char* m) {
      if (error) *error = m;
      return false;
    };
    if (ne <= 0 || nb < 2) return fail("snapshot: ne must be > 0 and nb >= 2");
    const size_t n = static_cast<size_t>(num_nodes());
    if (x.size() != 3 * n) return fail("snapshot: x must hold 3*ne*nb*nb values");
    if (!tau1.empty() && tau1.size() != n) return fail("snapshot: tau1 must hold ne*nb*nb");
    if (tau2.size() != tau1.size()) return fail("snapshot: tau2 must match tau1");
    if (!curvature.empty() && curvature.size() != n)
      return fail("snapshot: curvature must hold ne*nb*nb");
    if (!speed.empty() && speed.size() != n) return fail("snapshot: speed must hold ne*nb*nb");
    if (!bending.empty() && bending.size() != n)
      return fail("snapshot: bending must hold ne*nb*nb");
    return true;
  }
};

}  // namespace capflow::render
