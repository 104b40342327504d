#include "render/silhouette.h"

#include <cmath>

namespace capflow::render {

namespace {

// A point on the cell edge between vertices i and j where f crosses zero.
void add_crossing(const SurfaceMesh& m, int i, int j, float fi, float fj, OutlineLines* out) {
  const float a = fi / (fi - fj);  // f(i + a (j - i)) = 0
  float n[3], len = 0;
  for (int d = 0; d < 3; ++d) {
    out->position.push_back(m.position[3 * i + d] +
                            a * (m.position[3 * j + d] - m.position[3 * i + d]));
    n[d] = m.normal[3 * i + d] + a * (m.normal[3 * j + d] - m.normal[3 * i + d]);
    len += n[d] * n[d];
  }
  len = len > 0 ? 1.0f / std::sqrt(len) : 0.0f;
  for (float c : n) out->normal.push_back(c * len);
  out->value.push_back(m.value[i] + a * (m.value[j] - m.value[i]));
}

}  // namespace

void outline_segments(const SurfaceMesh& m, const Camera& cam, bool orthographic,
                      OutlineLines* out) {
  out->position.clear();
  out->normal.clear();
  out->value.clear();
  const int nv = m.num_vertices(), n = m.n;
  if (n < 2 || nv == 0) return;
  // f per vertex; the view matrix is rigid, so the eye is -R^T t and the direction towards the
  // viewer (orthographic) is the third row of R
  const auto& V = cam.view;
  float eye[3], dir[3];
  for (int c = 0; c < 3; ++c) {
    eye[c] = -(V[4 * c + 0] * V[12] + V[4 * c + 1] * V[13] + V[4 * c + 2] * V[14]);
    dir[c] = V[4 * c + 2];
  }
  std::vector<float> f(nv);
  for (int v = 0; v < nv; ++v) {
    const float* x = &m.position[3 * v];
    const float* nn = &m.normal[3 * v];
    f[v] = orthographic
               ? nn[0] * dir[0] + nn[1] * dir[1] + nn[2] * dir[2]
               : nn[0] * (eye[0] - x[0]) + nn[1] * (eye[1] - x[1]) + nn[2] * (eye[2] - x[2]);
  }
  const int elements = nv / (n * n);
  for (int e = 0; e < elements; ++e)
    for (int b = 0; b + 1 < n; ++b)
      for (int a = 0; a + 1 < n; ++a) {
        // corners counter-clockwise: 0 (a, b), 1 (a+1, b), 2 (a+1, b+1), 3 (a, b+1)
        const int c[4] = {(e * n + b) * n + a, (e * n + b) * n + a + 1, (e * n + b + 1) * n + a + 1,
                          (e * n + b + 1) * n + a};
        const float fc[4] = {f[c[0]], f[c[1]], f[c[2]], f[c[3]]};
        int crossing[4], k = 0;  // edges (q, q+1) with a sign change
        for (int q = 0; q < 4; ++q)
          if ((fc[q] < 0) != (fc[(q + 1) % 4] < 0)) crossing[k++] = q;
        if (k == 2) {
          for (int s = 0; s < 2; ++s) {
            const int q = crossing[s];
            add_crossing(m, c[q], c[(q + 1) % 4], fc[q], fc[(q + 1) % 4], out);
          }
        } else if (k == 4) {
          // saddle: pair the crossings so that the corners of the sign of the cell's mean are
          // joined
          const bool mean_neg = (fc[0] + fc[1] + fc[2] + fc[3]) < 0;
          const bool first_neg = fc[0] < 0;
          // if corner 0 shares the mean's sign, it is connected through the centre: cut corners
          // 1 and 3 off (edges 0-1 with 1-2, 2-3 with 3-0); otherwise cut 0 and 2 off
          const int pairs[2][2][2] = {{{0, 1}, {2, 3}}, {{3, 0}, {1, 2}}};
          const int(*pp)[2] = pairs[first_neg == mean_neg ? 0 : 1];
          for (int s = 0; s < 2; ++s)
            for (int t = 0; t < 2; ++t) {
              const int q = pp[s][t];
              add_crossing(m, c[q], c[(q + 1) % 4], fc[q], fc[(q + 1) % 4], out);
            }
        }
      }
}

}  // namespace capflow::render
