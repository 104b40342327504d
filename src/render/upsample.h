// capflow/render/upsample: spectral upsampling of a Snapshot for drawing (CPU only, no GL).
//
// Each element's tensor-product Lagrange interpolant through its NB x NB Gauss-Lobatto nodes
//   x(s, t) = sum_ij x_ij l_i(s) l_j(t)
// is evaluated on an n x n grid of equispaced parameters s_a = -1 + 2a/(n-1) (n = 25 by
// default, as in the paper's 3-D views), together with
//   x_s = sum_ij x_ij l_i'(s) l_j(t),  x_t = sum_ij x_ij l_i(s) l_j'(t),  n = x_s x x_t / |.|
// (outward, from the interpolant's own derivatives). The colour field is interpolated the
// same way from its nodal values. Each grid cell becomes two triangles.
//
// Seams: positions on a shared element edge depend only on the edge's shared nodes, so they
// agree between neighbours to rounding; the cross-edge derivative (hence the normal) and a
// field that is not single-valued at shared nodes differ slightly. Grid points that coincide
// (to 1e-6 of the bounding box) are welded: their position, normal (sum of unit normals,
// renormalised) and field value are averaged, so there is no shading or colour seam.
// Vertex v of element e at grid (a, b): index (e*n + b)*n + a.
#pragma once

#include <cstdint>
#include <vector>

#include "render/options.h"
#include "render/snapshot.h"

namespace capflow::render {

struct SurfaceMesh {
  int n = 0;                     // grid points per element direction
  std::vector<float> position;   // 3 per vertex
  std::vector<float> normal;     // 3 per vertex, unit
  std::vector<float> value;      // 1 per vertex: the colour field
  std::vector<uint32_t> triangles;  // 3 per triangle, counter-clockwise seen from outside
  std::vector<uint32_t> lines;      // 2 per segment: element edges
  float bbox_min[3] = {0, 0, 0}, bbox_max[3] = {0, 0, 0};
  float value_min = 0, value_max = 0;
  int num_vertices() const { return static_cast<int>(value.size()); }
};

// Nodal colour field of a snapshot: tau1, tau2, (tau1+tau2)/2, curvature, speed, bending, or 0 (Plain,
// or the array is not in the snapshot).
std::vector<double> nodal_field(const Snapshot& s, ColorField f);

class Upsampler {
 public:
  Upsampler(int nb, int n);  // throws std::invalid_argument for nb < 2 or n < 2
  // Fills *out (reusing its storage). Throws std::invalid_argument if s is not valid or its
  // nb differs from the constructor's.
  void build(const Snapshot& s, ColorField field, SurfaceMesh* out) const;

 private:
  int nb_, n_;
  std::vector<double> l_, dl_;  // n x nb row-major: l_i(s_a), l_i'(s_a)
};

}  // namespace capflow::render
