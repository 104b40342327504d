// capflow/app/surface_export: the ParaView surface of a capsule state (output/vtk.h's
// VtkSurface), on the element grids of n x n Gauss-Lobatto points per element.
//
// Each element's interpolant x(s, t) = sum_ij x_ij l_i(s) l_j(t) through its NB x NB nodes is
// evaluated at the n x n Gauss-Lobatto points of [-1, 1]^2 (n >= NB represents it exactly: the
// file is the solver's surface itself, which render and figure can read back as an n-node grid),
// with the unit normal x_s x x_t / |.| of the interpolant. The nodal fields are interpolated the
// same way: tau1, tau2 (principal tensions, G_s), mean_curvature (1/a, 1 on the unit sphere),
// and, when given, velocity (G a) and bending_energy_density ((kappa_b / 2)(2H - c0)^2, G_s).
// n = NB writes the nodes themselves.
#pragma once

#include <Eigen/Dense>

#include "geometry/mesh.h"
#include "output/vtk.h"
#include "render/snapshot.h"

namespace capflow::app {

// The fields of a state at its nodes (element-local layout, num_local columns / entries).
struct NodalState {
  const Eigen::Matrix3Xd* x = nullptr;         // positions
  const Eigen::Matrix3Xd* velocity = nullptr;  // optional
  const render::Snapshot* snapshot = nullptr;  // tensions, time, Ca and the shape diagnostics
  const Eigen::VectorXd* bending_energy = nullptr;  // optional (membrane::Bending::energy_density)
};

// The surface on n x n Gauss-Lobatto points per element (n >= 2; n = mesh.nb(): the nodes).
// Throws std::invalid_argument for n < 2 or fields of the wrong size.
output::VtkSurface surface_export(const geometry::Mesh& mesh, const NodalState& s, int n);

}  // namespace capflow::app
