// capflow/geometry/surface: differential geometry of a surface given by its node positions
// on a Mesh (the Lagrange representation of paper eq. 15).
//
// Per node, from the node's own element interpolant (shared nodes therefore carry one value
// per element; they agree to the discretisation error):
//   t_a = dx/dtheta_a (theta_1 = xi, theta_2 = eta), n = t1 x t2 / |t1 x t2| (outward),
//   sqrt(g) = |t1 x t2|, g_ab = t_a.t_b, b_ab = n . d^2x/dtheta_a dtheta_b,
//   mean curvature H = -(1/2) g^ab b_ab   (H = +1/R on a sphere of radius R, outward n),
//   Gaussian curvature K = det(b)/det(g).
// Everything uses only the Lagrange differentiation matrix (exact for degree NB-1).
#pragma once

#include <Eigen/Dense>

#include "geometry/mesh.h"

namespace capflow::geometry {

struct SurfaceGeometry {
  Matrix3Xd x, t1, t2, n, x11, x12, x22;
  VectorXd jac;  // sqrt(g)
  VectorXd g11, g12, g22, b11, b12, b22;
  VectorXd mean_curvature, gaussian_curvature;
};

SurfaceGeometry compute_geometry(const Mesh& mesh, const Matrix3Xd& x);

// Largest angle (rad) between the unit normals n (3 x num_local) of two neighbouring nodes
// along a grid line of an element, and the local index of the first of the two: how well the
// grid resolves the sharpest place of the surface.
double max_normal_turning(const Mesh& mesh, const Matrix3Xd& n, int* node = nullptr);

// Element-wise parametric derivatives of a nodal field f (rows x num_local; throws
// std::invalid_argument for another column count).
MatrixXd d_xi(const Mesh& mesh, const MatrixXd& f);
MatrixXd d_eta(const Mesh& mesh, const MatrixXd& f);

// Interpolant of one element and its derivatives at an arbitrary parameter point.
struct SurfacePoint {
  Vector3d x, xs, xt, xss, xst, xtt;
  Vector3d normal() const { return xs.cross(xt).normalized(); }
};

class ElementEvaluator {
 public:
  ElementEvaluator(const Mesh& mesh, const Matrix3Xd& x) : mesh_(mesh), x_(x) {}
  SurfacePoint eval(int e, double s, double t) const;

 private:
  const Mesh& mesh_;
  const Matrix3Xd& x_;
};

// The surface x (nodal positions on mesh `from`) carried to the nodes of mesh `to` through the
// reference sphere: node m of `to` gets the spectral interpolant of x at the material point
// to.reference().col(m) (Mesh::locate finds it on `from`). Changes NB and/or the element division
// of a shape; coincident nodes of `to` get identical positions. Exact for shapes whose elements
// are polynomials of degree < from.nb() in (xi, eta) when both meshes share the division.
Matrix3Xd resample_surface(const Mesh& from, const Matrix3Xd& x, const Mesh& to);

// The surface sampled at nq x nq Gauss-Legendre points of every element: positions, unit
// normals, tangents and the area weights w = w_s w_t sqrt(g), so INT F dS ~ sum_k F(x_k) w_k.
struct QuadratureSurface {
  int nq = 0;
  Matrix3Xd x, n, t1, t2;
  VectorXd w;
  Eigen::MatrixXd interp;  // nq x nb Lagrange interpolation matrix (node -> Gauss point)
};
QuadratureSurface sample_gauss(const Mesh& mesh, const Matrix3Xd& x, int nq);

// A nodal field (rows x num_local) at the Gauss points of sample_gauss (rows x ne*nq*nq);
// point (e, a, b) -> (e*nq + b)*nq + a.
MatrixXd to_gauss(const Mesh& mesh, const MatrixXd& f, const MatrixXd& interp);

}  // namespace capflow::geometry
