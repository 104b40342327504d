// Prints the validation tables of docs/validation.md section 1 (markdown):
//  1. max over all nodes of the mean-curvature error on the unit sphere, NB = 6..16, for each
//     element division (equiangular map), with the radial map at NE=6 for comparison;
//  2. area and volume relative errors of the unit sphere;
//  3. ellipsoid (1.8, 0.7, 1.0) diagnostics errors at NB = 14 for each division.
// Run by scripts/validate; every number is computed when it runs.
#include <cmath>
#include <cstdio>

#include "diagnostics/diagnostics.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"

using namespace capflow;
using namespace capflow::geometry;

namespace {
constexpr double kPi = 3.14159265358979323846;
double curvature_error(int ne, int nb, ElementMap map) {
  const Mesh mesh(ne, nb, map);
  const SurfaceGeometry g = compute_geometry(mesh, mesh.reference());
  return (g.mean_curvature.array() - 1.0).abs().maxCoeff();
}
}  // namespace

int main() {
  std::printf("Unit sphere, max |H - 1| over all nodes (edges and corners included); "
              "`build/tests/geometry/table_geometry`.\n\n");
  std::printf("| NB | NE=6 | NE=10 | NE=14 | NE=6 radial map |\n|---|---|---|---|---|\n");
  for (int nb = 6; nb <= 16; ++nb)
    std::printf("| %d | %.2e | %.2e | %.2e | %.2e |\n", nb,
                curvature_error(6, nb, ElementMap::Equiangular),
                curvature_error(10, nb, ElementMap::Equiangular),
                curvature_error(14, nb, ElementMap::Equiangular),
                curvature_error(6, nb, ElementMap::Radial));
  std::printf("\nUnit sphere area and volume, relative error (Gauss-Legendre, nq = NB+4):\n\n");
  std::printf("| NB | NE | area | volume |\n|---|---|---|---|\n");
  for (int nb : {10, 12, 14}) {
    for (int ne : {6, 10, 14}) {
      const Mesh mesh(ne, nb);
      diagnostics::ShapeOptions o;
      o.extrema = o.edge_curvature = false;
      const auto d = diagnostics::measure_shape(mesh, mesh.reference(), o);
      std::printf("| %d | %d | %.1e | %.1e |\n", nb, ne, std::abs(d.area / (4 * kPi) - 1),
                  std::abs(d.volume / (4 * kPi / 3) - 1));
    }
  }
  std::printf("\nEllipsoid (1.8, 0.7, 1.0), NB = 14: absolute errors of the diagnostics "
              "(edge curvature exact value 1.8/0.7^2 = 3.673469...):\n\n");
  std::printf("| NE | L | S | W | Lc | Sc | Wc | edge curvature |\n|---|---|---|---|---|---|---|---|\n");
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 14);
    const auto d = diagnostics::measure_shape(
        mesh, map_points(mesh.reference(), ellipsoid_map(1.8, 0.7, 1.0)));
    std::printf("| %d | %.1e | %.1e | %.1e | %.1e | %.1e | %.1e | %.1e |\n", ne,
                std::abs(d.L - 1.8), std::abs(d.S - 0.7), std::abs(d.W - 1.0),
                std::abs(d.Lc - 1.8), std::abs(d.Sc - 0.7), std::abs(d.Wc - 1.0),
                std::abs(d.edge_curvature - 1.8 / 0.49));
  }
  return 0;
}
