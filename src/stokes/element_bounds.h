// capflow/stokes/element_bounds: the bounds the operator decides an element's tier with (which
// rule a (target, element) pair takes), from the element's nodes only: the nodes' bounding
// sphere, the nearest node (geometry::nearest_node), and a margin for the points between the
// nodes.
#pragma once

#include <Eigen/Dense>

#include "geometry/mesh.h"

namespace capflow::stokes {

struct ElementBounds {
  Eigen::Vector3d centre;  // the mean of the element's nodes
  double radius = 0;       // the largest distance of a node from centre
  // A bound on the distance from any point of the element to its nearest node: 0.6 x the
  // longest diagonal of a cell of four neighbouring nodes (a point of a cell is within half its
  // diagonal of a corner; the margin covers the curvature between the nodes).
  double cell = 0;
};

// The bounds of element e (nodes e nb^2 .. (e + 1) nb^2 - 1 of x, nb x nb per element).
ElementBounds element_bounds(const Eigen::Matrix3Xd& x, int nb, int e);

// Whether a point of p (3 x n) may lie within distance th of element e: false only if for each
// point the nodes' sphere or the nearest node less the cell margin puts the whole element at th
// or beyond (so every decision of the operator that compares a distance with th, from the
// nearest node or from a nearest-point search, comes out >= th).
bool within_reach(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x, int e,
                  const ElementBounds& b, const Eigen::Matrix3Xd& p, double th);

}  // namespace capflow::stokes
