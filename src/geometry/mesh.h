// capflow/geometry/mesh: the spectral-element division of the reference (unit) sphere.
//
// The sphere is the projection of a cube [-1,1]^3 whose faces are split into curvilinear
// quadrilateral elements (paper fig. 1):
//   NE = 6 : one element per cube face.
//   NE = 10: the four faces parallel to x (+-y, +-z) split into two rows along x (x<0, x>0),
//            plus the two caps +-x.
//   NE = 14: the four faces parallel to y (+-x, +-z) split into three rows along y, plus the
//            two caps +-y. The rows divide the face's angular range into equal thirds.
// All three divisions are symmetric under the mirror planes x=0, y=0, z=0.
// Division::Box (the paper's "parallelepiped" projection, sec. 3.1) projects instead a box whose
// face regions are all unit squares: NE=10 the box [-2,2] x [-1,1]^2 (the faces parallel to x
// split at x = 0; the caps +-x then span 2 atan(1/2) = 53 degrees instead of 90), NE=14 the box
// [-1,1] x [-3,3] x [-1,1] (rows at y = +-1: the middle rows span 90 degrees, the caps +-y
// 2 atan(1/3) = 37); NE=6 is the cube either way. Along each box axis k the coordinate is
// d_k tan(beta) with beta linear in the element parameter, d_k the nearest distance of a face
// parallel to k (1 on both boxes): a map of the axis alone, so neighbouring faces share their
// edge nodes, and equiangular on the faces at distance d_k.
// Division::Diagonal (NE=6 only) is the cube turned by 45 degrees about z: its faces have the
// normals (+-1, +-1, 0)/sqrt(2) and (0, 0, +-1), so the +-x and +-y axes pierce the middles of
// element edges instead of face centres. In planar extension the tips (+-x) then lie on an
// edge, where the Gauss-Lobatto nodes of the two elements cluster, instead of in the middle of
// a 90-degree cap where they are sparsest. It keeps the mirror planes x=0, y=0, z=0. The
// patches below describe the unturned cube; sphere_point and locate apply the turn.
//
// Element parametrisation (xi, eta) in [-1,1]^2. On a face with normal axis a and sign s, xi
// runs along box axis tu and eta along tv, chosen so that t_xi x t_eta points outward. With
// the default EQUIANGULAR map the cube coordinate is tan(alpha) with alpha linear in xi
// (alpha from atan(u0) to atan(u1) for a patch covering [u0, u1] of the face); the RADIAL
// (gnomonic) map is linear in the cube coordinate and kept only for comparison.
//
// Nodes: NB x NB Gauss-Lobatto points per element; local index (e, i, j) -> (e*NB + j)*NB + i,
// i along xi, j along eta. Nodes on element edges/corners are shared (coincident) by 2, 3 or 4
// elements; `unique_of` numbers the distinct nodes and `classes` lists each class's locals.
// `mirror[k][m]` is the local node at the position of local node m reflected in the plane
// x_k = 0 (in the mirror-image element, so element-local data maps consistently).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace capflow::geometry {

using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

enum class ElementMap { Equiangular, Radial };
enum class Division { Cube, Box, Diagonal };

struct Patch {
  int axis = 0;   // face normal axis (0=x, 1=y, 2=z)
  int sign = 1;   // +1 or -1
  int tu = 1;     // box axis along xi
  int tv = 2;     // box axis along eta
  double a0 = 0, a1 = 0;  // angle range along xi: alpha(xi) = a0 + (a1-a0)(xi+1)/2
  double b0 = 0, b1 = 0;  // angle range along eta
};

class Mesh {
 public:
  // ne in {6, 10, 14}; nb in [3, 64]; Division::Diagonal needs ne = 6. Throws
  // std::invalid_argument otherwise.
  Mesh(int ne, int nb, ElementMap map = ElementMap::Equiangular,
       Division division = Division::Cube);

  int ne() const { return ne_; }
  int nb() const { return nb_; }
  ElementMap map() const { return map_; }
  Division division() const { return division_; }
  // Half-extents of the projected box ((1,1,1) for the cube).
  const Vector3d& box() const { return box_; }
  int nodes_per_element() const { return nb_ * nb_; }
  int num_local() const { return ne_ * nb_ * nb_; }
  int num_unique() const { return static_cast<int>(classes_.size()); }
  int local(int e, int i, int j) const { return (e * nb_ + j) * nb_ + i; }

  const VectorXd& nodes() const { return xi_; }         // Gauss-Lobatto nodes on [-1,1]
  const VectorXd& bary() const { return bw_; }          // their barycentric weights
  const MatrixXd& diff() const { return d_; }           // differentiation matrix
  const std::vector<Patch>& patches() const { return patches_; }

  // Reference sphere node positions, 3 x num_local().
  const Matrix3Xd& reference() const { return ref_; }
  // The exact reference sphere point at parameters (xi, eta) of element e.
  Vector3d sphere_point(int e, double xi, double eta) const;
  // The inverse of sphere_point: the element holding the direction p (any p != 0; it is taken
  // as the sphere point p/|p|) and its parameters there, in [-1,1]^2. A point on an element
  // edge goes to the first element (in element order) that holds it.
  struct Location {
    int e = -1;
    double xi = 0, eta = 0;
  };
  Location locate(const Vector3d& p) const;

  const std::vector<int>& unique_of() const { return unique_of_; }
  const std::vector<std::vector<int>>& classes() const { return classes_; }
  const std::vector<int>& mirror(int axis) const { return mirror_[axis]; }
  // Element that is the mirror image of element e in the plane x_axis = 0.
  int mirror_element(int e, int axis) const { return mirror_elem_[axis][e]; }

 private:
  void build_patches();
  void build_coincidence();
  void build_mirrors();
  // The turn of the diagonal division (identity otherwise): sense +1 from the cube frame to
  // the sphere, -1 back.
  Vector3d turn(const Vector3d& p, int sense) const;

  int ne_, nb_;
  ElementMap map_;
  Division division_;
  Vector3d box_, axis_scale_;
  VectorXd xi_, bw_;
  MatrixXd d_;
  std::vector<Patch> patches_;
  Matrix3Xd ref_;
  std::vector<int> unique_of_;
  std::vector<std::vector<int>> classes_;
  std::array<std::vector<int>, 3> mirror_;
  std::array<std::vector<int>, 3> mirror_elem_;
};

}  // namespace capflow::geometry
