// capflow/diagnostics: shape measures of a capsule surface given on a Mesh (method.md sec. 7,
// paper secs. 4 and 6). Lengths in units of the capsule radius a.
//
//   area      A   = INT dS
//   volume    V   = (1/3) INT x.n dS
//   centroid  x_c = (1/V) INT (|x|^2/2) n dS
//   inertia   M_ij = INT_V xi_i xi_j dV = (1/5) INT xi_i xi_j (xi.n) dS,  xi = x - x_c;
//             the inertia-ellipsoid semi-axes are a_k = sqrt(5 m_k / V) for the eigenvalues
//             m_k of M (an ellipsoid's own semi-axes are recovered exactly).
//   L, S, W   semi-axes assigned by AxesMode (below); D = (L - S)/(L + S) (paper eq. 22).
//   Lc = max |x - x_c|, Sc = min |x - x_c|, Wc = max |z - z_c| over the spectral surface,
//             found by box-constrained Newton on the element interpolants, started from the
//             best node (so extrema on element edges and corners are found too).
//   edge_curvature: curvature of the z = z_c profile at its tip on the +x axis through x_c,
//             = the normal curvature along e_y there (Meusnier): with d^a = g^ab (t_b.e_y),
//             kappa = |b_ab d^a d^b| / (g_ab d^a d^b). The crossing is found by Newton in
//             every element from its node closest to the axis, the outermost one taken; NaN
//             (tip = x_c) if the axis meets no element (x_c outside a bent body).
// Integrals use nq x nq Gauss-Legendre points per element (default nq = NB + 4).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/surface.h"

namespace capflow::diagnostics {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using geometry::Matrix3Xd;
using geometry::Mesh;

enum class AxesMode {
  // Planar extension: L, S, W are the inertia semi-axes whose directions are closest to
  // x, y, z respectively.
  FlowAxes,
  // Simple shear u = (z, 0, 0): W is the semi-axis closest to the vorticity axis y; L and S
  // are the major and minor of the other two (in the x-z plane); inclination is the angle of
  // L's axis from +x towards +z, in (-90, 90] degrees.
  Shear,
};

struct ShapeOptions {
  AxesMode axes = AxesMode::FlowAxes;
  int nq = 0;                  // Gauss points per direction for integrals; 0 -> NB + 4
  bool extrema = true;         // compute Lc, Sc, Wc
  bool edge_curvature = true;  // compute the +x tip curvature
};

struct ShapeDiagnostics {
  double area = 0, volume = 0;
  Vector3d centroid = Vector3d::Zero();
  Matrix3d inertia = Matrix3d::Zero();          // M_ij
  Vector3d semi_axes = Vector3d::Zero();        // sorted descending
  Matrix3d axis_directions = Matrix3d::Zero();  // columns match semi_axes
  double L = 0, S = 0, W = 0, D = 0;
  double inclination_deg = 0;  // AxesMode::Shear only
  double Lc = 0, Sc = 0, Wc = 0;
  double edge_curvature = 0;
  Vector3d tip = Vector3d::Zero();  // where edge_curvature was taken
};

ShapeDiagnostics measure_shape(const Mesh& mesh, const Matrix3Xd& x,
                               const ShapeOptions& options = {});

// Points of the cross-section of the surface with the plane x_axis = value, as in-plane
// coordinates (the two other axes in increasing order: plane z: (x, y); plane y: (x, z);
// plane x: (y, z)), ordered by angle about `center` (in-plane coordinates). Each element is
// cut along 4*NB parameter lines in each direction; roots are refined by Newton to 1e-13.
std::vector<Vector2d> cross_section(const Mesh& mesh, const Matrix3Xd& x, int axis, double value,
                                    const Vector2d& center = Vector2d::Zero());

}  // namespace capflow::diagnostics
