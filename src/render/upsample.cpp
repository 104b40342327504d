#include "render/upsample.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <array>
#include <map>

#include "spectral/spectral.h"

namespace capflow::render {

std::vector<double> nodal_field(const Snapshot& s, ColorField f) {
  const size_t n = static_cast<size_t>(s.num_nodes());
  std::vector<double> v(n, 0.0);
  if (f == ColorField::MeanCurvature || f == ColorField::Speed || f == ColorField::BendingEnergy) {
    const std::vector<double>& a = f == ColorField::Speed           ? s.speed
                                   : f == ColorField::BendingEnergy ? s.bending
                                                                    : s.curvature;
    if (a.size() == n) v = a;
    return v;
  }
  if (f == ColorField::Plain || s.tau1.size() != n) return v;
  for (size_t k = 0; k < n; ++k) {
    switch (f) {
      case ColorField::MaxTension: v[k] = s.tau1[k]; break;
      case ColorField::MinTension: v[k] = s.tau2[k]; break;
      default: v[k] = 0.5 * (s.tau1[k] + s.tau2[k]); break;
    }
  }
  return v;
}

Upsampler::Upsampler(int nb, int n) : nb_(nb), n_(n) {
  if (nb < 2 || n < 2) throw std::invalid_argument("Upsampler: need nb >= 2 and n >= 2");
  const auto rule = spectral::gauss_lobatto(nb);
  Eigen::VectorXd t(n);
  for (int a = 0; a < n; ++a) t[a] = -1.0 + 2.0 * a / (n - 1);
  t[0] = -1.0;
  t[n - 1] = 1.0;
  const Eigen::MatrixXd L = spectral::interpolation_matrix(rule.x, t);
  const Eigen::MatrixXd D = spectral::derivative_matrix(rule.x, t);
  l_.resize(static_cast<size_t>(n) * nb);
  dl_.resize(l_.size());
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < nb; ++i) {
      l_[static_cast<size_t>(a) * nb + i] = L(a, i);
      dl_[static_cast<size_t>(a) * nb + i] = D(a, i);
    }
}

void Upsampler::build(const Snapshot& s, ColorField field, SurfaceMesh* out) const {
  std::string err;
  if (!s.IsValid(&err)) throw std::invalid_argument(err);
  if (s.nb != nb_) throw std::invalid_argument("Upsampler: snapshot nb differs");
  const int ne = s.ne, nb = nb_, n = n_;
  const std::vector<double> f = nodal_field(s, field);
  const size_t nv = static_cast<size_t>(ne) * n * n;
  out->n = n;
  out->position.assign(3 * nv, 0.f);
  out->normal.assign(3 * nv, 0.f);
  out->value.assign(nv, 0.f);

  // Per element: first contract along i (xi): A(a, j) = sum_i l_i(s_a) X(i, j), and the same
  // with l'; then along j. 4 quantities (x,y,z,f) x 2 (value, xi-derivative).
  std::vector<double> A(static_cast<size_t>(n) * nb * 4), Ad(A.size());
  for (int e = 0; e < ne; ++e) {
    const size_t base = static_cast<size_t>(e) * nb * nb;
    std::fill(A.begin(), A.end(), 0.0);
    std::fill(Ad.begin(), Ad.end(), 0.0);
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) {
        const size_t k = base + static_cast<size_t>(j) * nb + i;
        const double q[4] = {s.x[3 * k], s.x[3 * k + 1], s.x[3 * k + 2], f[k]};
        for (int a = 0; a < n; ++a) {
          const double li = l_[static_cast<size_t>(a) * nb + i];
          const double dli = dl_[static_cast<size_t>(a) * nb + i];
          double* pa = &A[(static_cast<size_t>(a) * nb + j) * 4];
          double* pd = &Ad[(static_cast<size_t>(a) * nb + j) * 4];
          for (int c = 0; c < 4; ++c) {
            pa[c] += li * q[c];
            pd[c] += dli * q[c];
          }
        }
      }
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        double x[4] = {0, 0, 0, 0}, xs[3] = {0, 0, 0}, xt[3] = {0, 0, 0};
        for (int j = 0; j < nb; ++j) {
          const double lj = l_[static_cast<size_t>(b) * nb + j];
          const double dlj = dl_[static_cast<size_t>(b) * nb + j];
          const double* pa = &A[(static_cast<size_t>(a) * nb + j) * 4];
          const double* pd = &Ad[(static_cast<size_t>(a) * nb + j) * 4];
          for (int c = 0; c < 4; ++c) x[c] += lj * pa[c];
          for (int c = 0; c < 3; ++c) {
            xs[c] += lj * pd[c];
            xt[c] += dlj * pa[c];
          }
        }
        double nrm[3] = {xs[1] * xt[2] - xs[2] * xt[1], xs[2] * xt[0] - xs[0] * xt[2],
                         xs[0] * xt[1] - xs[1] * xt[0]};
        const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        const size_t v = (static_cast<size_t>(e) * n + b) * n + a;
        for (int c = 0; c < 3; ++c) {
          out->position[3 * v + c] = static_cast<float>(x[c]);
          out->normal[3 * v + c] = len > 0 ? static_cast<float>(nrm[c] / len) : 0.f;
        }
        out->value[v] = static_cast<float>(x[3]);
      }
  }

  // Bounding box.
  for (int c = 0; c < 3; ++c) {
    out->bbox_min[c] = out->bbox_max[c] = out->position[c];
  }
  for (size_t v = 0; v < nv; ++v)
    for (int c = 0; c < 3; ++c) {
      out->bbox_min[c] = std::min(out->bbox_min[c], out->position[3 * v + c]);
      out->bbox_max[c] = std::max(out->bbox_max[c], out->position[3 * v + c]);
    }
  float diag = 0;
  for (int c = 0; c < 3; ++c) diag = std::max(diag, out->bbox_max[c] - out->bbox_min[c]);
  const double h = 1e-6 * std::max(diag, 1e-30f);

  // Weld coincident boundary grid points.
  struct Acc {
    double p[4] = {0, 0, 0, 0}, nn[3] = {0, 0, 0};
    int count = 0;
  };
  using Key = std::array<long long, 3>;
  auto key_of = [&](size_t v) {
    Key k;
    for (int c = 0; c < 3; ++c) k[c] = std::llround(out->position[3 * v + c] / h);
    return k;
  };
  std::map<Key, Acc> groups;
  std::vector<size_t> boundary;
  for (int e = 0; e < ne; ++e)
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        if (a != 0 && a != n - 1 && b != 0 && b != n - 1) continue;
        const size_t v = (static_cast<size_t>(e) * n + b) * n + a;
        boundary.push_back(v);
        Acc& g = groups[key_of(v)];
        for (int c = 0; c < 3; ++c) {
          g.p[c] += out->position[3 * v + c];
          g.nn[c] += out->normal[3 * v + c];
        }
        g.p[3] += out->value[v];
        ++g.count;
      }
  for (size_t v : boundary) {
    const Acc& g = groups[key_of(v)];
    if (g.count < 2) continue;
    const double len = std::sqrt(g.nn[0] * g.nn[0] + g.nn[1] * g.nn[1] + g.nn[2] * g.nn[2]);
    for (int c = 0; c < 3; ++c) {
      out->position[3 * v + c] = static_cast<float>(g.p[c] / g.count);
      if (len > 0) out->normal[3 * v + c] = static_cast<float>(g.nn[c] / len);
    }
    out->value[v] = static_cast<float>(g.p[3] / g.count);
  }

  out->value_min = *std::min_element(out->value.begin(), out->value.end());
  out->value_max = *std::max_element(out->value.begin(), out->value.end());

  // Topology depends only on (ne, n): rebuild only when it changed.
  const size_t ntri = static_cast<size_t>(ne) * (n - 1) * (n - 1) * 2;
  if (out->triangles.size() != 3 * ntri) {
    out->triangles.clear();
    out->triangles.reserve(3 * ntri);
    out->lines.clear();
    for (int e = 0; e < ne; ++e) {
      auto id = [&](int a, int b) { return static_cast<uint32_t>((e * n + b) * n + a); };
      for (int b = 0; b + 1 < n; ++b)
        for (int a = 0; a + 1 < n; ++a) {
          // (s, t) is right-handed with the outward normal: counter-clockwise from outside.
          out->triangles.insert(out->triangles.end(), {id(a, b), id(a + 1, b), id(a + 1, b + 1)});
          out->triangles.insert(out->triangles.end(), {id(a, b), id(a + 1, b + 1), id(a, b + 1)});
        }
      for (int k = 0; k + 1 < n; ++k) {
        out->lines.insert(out->lines.end(), {id(k, 0), id(k + 1, 0)});
        out->lines.insert(out->lines.end(), {id(k, n - 1), id(k + 1, n - 1)});
        out->lines.insert(out->lines.end(), {id(0, k), id(0, k + 1)});
        out->lines.insert(out->lines.end(), {id(n - 1, k), id(n - 1, k + 1)});
      }
    }
  }
}

}  // namespace capflow::render
