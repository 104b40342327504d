// capflow/geometry/element_search: the minimum of a function of position over one element of
// the interpolated surface (paper eq. 15), by a projected Newton iteration in the element's
// parameters (s, t) in [-1, 1]^2. Shared by the near-singular quadrature (the nearest point of
// an element to a target) and the diagnostics (extents Lc, Sc, Wc of the surface).
//
// The function is a quadratic of position, psi(x) = a/2 |x - c|^2 + b.x: a = 1, b = 0 is the
// squared distance to c over two, a = -1 its negative (farthest point), a = 0 a linear height.
//
// Method: an active set (a coordinate on the boundary of the square whose gradient points
// outwards is held fixed), Newton in the free coordinates with the Hessian of psi(x(s, t));
// where that is not positive definite, the metric a J^T J (a > 0) or J^T J (a <= 0) instead;
// the clipped step is halved until psi does not increase (clipping a full 2-D step instead can
// stall at a corner that is not the minimum). Ends when a step moves (s, t) by < 1e-13, after
// 50 iterations, or at a corner satisfying the optimality conditions. Converges to a local
// minimum of the element (the global one from a start near it: callers start at the best node).
#pragma once

#include <Eigen/Dense>

#include "geometry/mesh.h"
#include "geometry/surface.h"

namespace capflow::geometry {

struct QuadraticOfPosition {
  double a = 1.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double value(const Eigen::Vector3d& x) const {
    return 0.5 * a * (x - c).squaredNorm() + b.dot(x);
  }
  Eigen::Vector3d grad(const Eigen::Vector3d& x) const { return a * (x - c) + b; }
};

struct ElementMinimum {
  double s = 0, t = 0;  // parameters of the minimum
  SurfacePoint p;       // the surface there (position and derivatives)
  double value = 0;     // psi(p.x)
};

// The minimum of psi over element e, from (s, t).
ElementMinimum minimise_on_element(const ElementEvaluator& ev, const QuadraticOfPosition& psi,
                                   int e, double s, double t);

// The nearest point of element e of the surface x to x0: from the element's nearest node.
// h = the distance, (s, t) its parameters, xs, xt the tangents there.
struct NearestPoint {
  double s = 0, t = 0, h = 0;
  Eigen::Vector3d xs, xt;
};
// The distance from x0 to the nearest node of element e of the surface x; *node (if given) that
// node's local index 0..nb^2-1.
double nearest_node(const Mesh& mesh, const Eigen::Matrix3Xd& x, int e, const Eigen::Vector3d& x0,
                    int* node = nullptr);
// start_node: the element's nearest node (local index 0..nb^2-1) when the caller has it, -1 to
// search for it.
NearestPoint nearest_point(const Mesh& mesh, const Eigen::Matrix3Xd& x, int e,
                           const Eigen::Vector3d& x0, int start_node = -1);

}  // namespace capflow::geometry
