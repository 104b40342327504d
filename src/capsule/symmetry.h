// capflow/capsule/symmetry: reduction of the velocity evaluation by the flow's symmetries.
//
// Planar extension keeps the mirror planes x=0, y=0, z=0: the velocity is computed only at the
// nodes of the closed positive octant (one node per coincidence class) and copied to the other
// nodes by u(R x) = R u(x), R = diag(+-1, +-1, +-1) (about 8x fewer targets).
// Simple shear u = (z, 0, 0) keeps the mirror y -> -y and the point reflection
// (x, z) -> (-x, -z): targets with y >= 0 and x >= 0 (about 4x fewer).
// A custom gradient G gets the octant when it is diagonal and the shear pair when y decouples
// from x and z (capsule.cpp, symmetry_for); any other G is evaluated at every node.
// The maps act on node labels through the mesh's mirror maps (material points), so they hold
// for every deformed state that started symmetric (the initial sphere).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "geometry/mesh.h"
#include "stokes/boundary_integral.h"

namespace capflow::capsule {

enum class SymmetryKind { None, Octant, Shear };

class SymmetryMap {
 public:
  SymmetryMap(const geometry::Mesh& mesh, SymmetryKind kind);

  SymmetryKind kind() const { return kind_; }
  // Local nodes at which the velocity must be computed (one per coincidence class).
  const std::vector<int>& targets() const { return targets_; }
  // Expands values at targets() (3 x targets) to every local node (3 x num_local).
  void expand(const Eigen::Matrix3Xd& at_targets, Eigen::Matrix3Xd* all) const;
  // The same map for the operators' assembled forms (stokes::NodeExpansion: columns = targets).
  stokes::NodeExpansion expansion() const;

 private:
  SymmetryKind kind_;
  std::vector<int> targets_;
  std::vector<int> source_;            // local node -> index into targets_
  std::vector<Eigen::Vector3d> sign_;  // local node -> component signs
};

}  // namespace capflow::capsule
