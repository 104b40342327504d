// capflow/stokes/far_field: the far tiers of the boundary operators (boundary_integral.h): the
// surface and density at the nq x nq Gauss-Legendre points of every element, filled once per
// call, and the kernel sums over them (the single layer's loop cloned for x86-64-v4/v3 and the
// baseline like the special rules' loops).
#pragma once

#include <Eigen/Dense>

#include "geometry/mesh.h"
#include "stokes/kernel_mode.h"
#include "stokes/line_sums.h"

namespace capflow::stokes {

// A far tier's Gauss rule (nq points) and its interpolation / derivative matrices from the
// element nodes.
struct FarBasis {
  Eigen::VectorXd w;
  Eigen::MatrixXd I, Id;  // nq x nb
};
FarBasis far_basis(const Eigen::VectorXd& nodes, int nq);

// Far-field data at the Gauss points, row-major rows: 0-2 x, 3-5 the density, 6-8
// w (x_xi x x_eta) (not written for the single layer, which reads only w J), 9 w J.
struct FarData {
  int nq = 0;
  RowMat d;
};

// The two parts of far_data: the surface rows (0-2, 6-9) and esize, which need only x, and the
// density rows (3-5, zero for the modes without a density). A call makes the first while the
// density is being computed (boundary_integral.h).
template <Mode M>
void far_geometry(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x, const FarBasis& fb, int e,
                  FarData& F, double* esize);
template <Mode M>
void far_density(const geometry::Mesh& mesh, const Eigen::Matrix3Xd* dens, const FarBasis& fb,
                 int e, FarData& F);

// Far-field data of element e at the nq x nq Gauss-Legendre points of fb into columns
// [e nq^2, (e + 1) nq^2) of F.d (rows as FarData says).
// esize (optional): the element's size, the mean length of its longer family of coordinate
// lines.
template <Mode M>
void far_data(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd* dens,
              const FarBasis& fb, int e, FarData& F, double* esize);

// Kernel sum over the far points [q0, q1) of F.
template <Mode M>
void far_sum(const FarData& F, int q0, int q1, const Eigen::Vector3d& x0, const Eigen::Vector3d& u0,
             double* acc);

}  // namespace capflow::stokes
