#include "stokes/element_bounds.h"

#include "geometry/element_search.h"

#include <algorithm>
#include <cmath>

namespace capflow::stokes {

ElementBounds element_bounds(const Eigen::Matrix3Xd& x, int nb, int e) {
  const int nb2 = nb * nb;
  ElementBounds b;
  b.centre = x.middleCols(e * nb2, nb2).rowwise().mean();
  for (int k = 0; k < nb2; ++k)
    b.radius = std::max(b.radius, (x.col(e * nb2 + k) - b.centre).norm());
  double diag = 0;
  for (int j = 0; j + 1 < nb; ++j)
    for (int i = 0; i + 1 < nb; ++i) {
      const int q = e * nb2 + j * nb + i;
      diag = std::max(diag, std::max((x.col(q) - x.col(q + nb + 1)).norm(),
                                     (x.col(q + 1) - x.col(q + nb)).norm()));
    }
  b.cell = 0.6 * diag;
  return b;
}

bool within_reach(const geometry::Mesh& mesh, const Eigen::Matrix3Xd& x, int e,
                  const ElementBounds& b, const Eigen::Matrix3Xd& p, double th) {
  for (Eigen::Index k = 0; k < p.cols(); ++k) {
    const Eigen::Vector3d x0 = p.col(k);
    // the nearest node is at least the sphere's distance away
    if ((x0 - b.centre).norm() - b.radius - b.cell >= th) continue;
    if (geometry::nearest_node(mesh, x, e, x0) - b.cell < th) return true;
  }
  return false;
}

}  // namespace capflow::stokes
