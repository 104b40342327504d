#include "geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "spectral/spectral.h"

namespace capflow::geometry {

namespace {
constexpr double kQuarterPi = 0.78539816339744830962;
constexpr double kMatchTol = 1e-10;
}  // namespace

Mesh::Mesh(int ne, int nb, ElementMap map, Division division)
    : ne_(ne), nb_(nb), map_(map), division_(division), box_(1, 1, 1) {
  if (ne != 6 && ne != 10 && ne != 14)
    throw std::invalid_argument("Mesh: elements must be 6, 10 or 14, got " + std::to_string(ne));
  if (division == Division::Diagonal && ne != 6)
    throw std::invalid_argument("Mesh: the diagonal division needs 6 elements, got " +
                                std::to_string(ne));
  if (division == Division::Box) box_ = ne == 10 ? Vector3d(2, 1, 1) : ne == 14 ? Vector3d(1, 3, 1) : box_;
  for (int k = 0; k < 3; ++k) axis_scale_[k] = std::min(box_[(k + 1) % 3], box_[(k + 2) % 3]);
  if (nb < 3 || nb > 64)
    throw std::invalid_argument("Mesh: nb must be in [3, 64], got " + std::to_string(nb));
  const spectral::Rule r = spectral::gauss_lobatto(nb);
  xi_ = r.x;
  bw_ = spectral::barycentric_weights(xi_);
  d_ = spectral::differentiation_matrix(xi_);
  build_patches();
  ref_.resize(3, num_local());
  for (int e = 0; e < ne_; ++e)
    for (int j = 0; j < nb_; ++j)
      for (int i = 0; i < nb_; ++i) ref_.col(local(e, i, j)) = sphere_point(e, xi_[i], xi_[j]);
  build_coincidence();
  build_mirrors();
}

void Mesh::build_patches() {
  // Split axis and number of rows: NE=10 splits the faces parallel to x in 2 rows along x;
  // NE=14 splits the faces parallel to y in 3 rows along y.
  const int split_axis = (ne_ == 10) ? 0 : (ne_ == 14 ? 1 : -1);
  const int rows = (ne_ == 10) ? 2 : (ne_ == 14 ? 3 : 1);
  for (int a = 0; a < 3; ++a) {
    for (int s : {1, -1}) {
      Patch p;
      p.axis = a;
      p.sign = s;
      p.tu = (s > 0) ? (a + 1) % 3 : (a + 2) % 3;
      p.tv = (s > 0) ? (a + 2) % 3 : (a + 1) % 3;
      // Along box axis k the coordinate is u = d_k tan(beta), beta linear in the element
      // parameter, d_k the nearest distance of a face parallel to k (axis_scale_): a map of the
      // axis alone, so faces sharing an edge put their nodes at the same points of it, and
      // equiangular as seen from the faces at distance d_k (on the cube: the equiangular map).
      p.a1 = std::atan(box_[p.tu] / axis_scale_[p.tu]);  // pi/4 on the cube
      p.b1 = std::atan(box_[p.tv] / axis_scale_[p.tv]);
      p.a0 = -p.a1;
      p.b0 = -p.b1;
      if (split_axis < 0 || split_axis == a) {
        patches_.push_back(p);
        continue;
      }
      // Row k covers [lo_k, hi_k] of the split axis: equal angles on the cube, equal lengths
      // (unit squares) on the box.
      const double w = 2.0 * kQuarterPi / rows;
      auto lo = [&](int k) {  // box: the row boundaries at the unit-square edges
        const double h = box_[split_axis];
        return division_ == Division::Cube
                   ? -kQuarterPi + k * w
                   : std::atan((-h + k * 2.0 * h / rows) / axis_scale_[split_axis]);
      };
      for (int k = 0; k < rows; ++k) {
        Patch q = p;
        if (p.tu == split_axis) {
          q.a0 = lo(k);
          q.a1 = lo(k + 1);
        } else {
          q.b0 = lo(k);
          q.b1 = lo(k + 1);
        }
        patches_.push_back(q);
      }
    }
  }
  if (static_cast<int>(patches_.size()) != ne_)
    throw std::logic_error("Mesh: patch construction produced a wrong element count");
}

Vector3d Mesh::sphere_point(int e, double xi, double eta) const {
  const Patch& p = patches_[e];
  auto coord = [this](double lo, double hi, double t) {
    if (map_ == ElementMap::Equiangular) return std::tan(lo + (hi - lo) * 0.5 * (t + 1.0));
    return std::tan(lo) + (std::tan(hi) - std::tan(lo)) * 0.5 * (t + 1.0);
  };
  Vector3d c;
  c[p.axis] = p.sign * box_[p.axis];
  c[p.tu] = axis_scale_[p.tu] * coord(p.a0, p.a1, xi);
  c[p.tv] = axis_scale_[p.tv] * coord(p.b0, p.b1, eta);
  return turn(c.normalized(), 1);
}

Vector3d Mesh::turn(const Vector3d& p, int sense) const {
  if (division_ != Division::Diagonal) return p;
  // rotation by sense * 45 degrees about z
  constexpr double kHalfSqrt2 = 0.70710678118654752440;
  const double s = sense * kHalfSqrt2;
  return {kHalfSqrt2 * p.x() - s * p.y(), s * p.x() + kHalfSqrt2 * p.y(), p.z()};
}

Mesh::Location Mesh::locate(const Vector3d& direction) const {
  const Vector3d p = turn(direction, -1);
  // the box face the ray through p meets first: the largest |p_k| / box_k
  int a = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(p[k]) * box_[a] > std::abs(p[a]) * box_[k]) a = k;
  if (!(std::abs(p[a]) > 0)) throw std::invalid_argument("Mesh::locate: the direction is zero or NaN");
  const int sign = p[a] > 0 ? 1 : -1;
  // Parameter of cube coordinate c on a patch covering angles [lo, hi] (inverse of the map in
  // sphere_point).
  auto param = [this](double lo, double hi, double c) {
    if (map_ == ElementMap::Equiangular) return 2.0 * (std::atan(c) - lo) / (hi - lo) - 1.0;
    return 2.0 * (c - std::tan(lo)) / (std::tan(hi) - std::tan(lo)) - 1.0;
  };
  constexpr double kTol = 1e-12;
  for (int e = 0; e < ne_; ++e) {
    const Patch& q = patches_[e];
    if (q.axis != a || q.sign != sign) continue;
    const double xi = param(q.a0, q.a1, p[q.tu] * box_[a] / (std::abs(p[a]) * axis_scale_[q.tu]));
    const double eta = param(q.b0, q.b1, p[q.tv] * box_[a] / (std::abs(p[a]) * axis_scale_[q.tv]));
    if (std::abs(xi) <= 1.0 + kTol && std::abs(eta) <= 1.0 + kTol)
      return {e, std::clamp(xi, -1.0, 1.0), std::clamp(eta, -1.0, 1.0)};
  }
  // Unreachable for a division that tiles the cube: every face is covered by its patches.
  throw std::logic_error("Mesh::locate: no element holds the direction");
}

void Mesh::build_coincidence() {
  const int n = num_local();
  unique_of_.assign(n, -1);
  std::vector<int> boundary;
  for (int e = 0; e < ne_; ++e)
    for (int j = 0; j < nb_; ++j)
      for (int i = 0; i < nb_; ++i)
        if (i == 0 || j == 0 || i == nb_ - 1 || j == nb_ - 1) boundary.push_back(local(e, i, j));
  // Interior nodes first get their own classes in element order; boundary nodes are grouped
  // by position (all-pairs over boundary nodes only).
  for (int m = 0; m < n; ++m) {
    if (unique_of_[m] >= 0) continue;
    const int e = m / (nb_ * nb_);
    const int i = m % nb_, j = (m / nb_) % nb_;
    const bool on_boundary = (i == 0 || j == 0 || i == nb_ - 1 || j == nb_ - 1);
    const int id = static_cast<int>(classes_.size());
    classes_.push_back({m});
    unique_of_[m] = id;
    if (!on_boundary) continue;
    for (int q : boundary) {
      if (q <= m || unique_of_[q] >= 0 || q / (nb_ * nb_) == e) continue;
      if ((ref_.col(q) - ref_.col(m)).norm() < kMatchTol) {
        unique_of_[q] = id;
        classes_.back().push_back(q);
      }
    }
  }
}

void Mesh::build_mirrors() {
  for (int k = 0; k < 3; ++k) {
    mirror_elem_[k].assign(ne_, -1);
    mirror_[k].assign(num_local(), -1);
    for (int e = 0; e < ne_; ++e) {
      Vector3d c = sphere_point(e, 0.0, 0.0);
      c[k] = -c[k];
      for (int f = 0; f < ne_; ++f)
        if ((sphere_point(f, 0.0, 0.0) - c).norm() < kMatchTol) mirror_elem_[k][e] = f;
      if (mirror_elem_[k][e] < 0)
        throw std::logic_error("Mesh: division is not mirror symmetric (element " +
                               std::to_string(e) + ")");
      const int f = mirror_elem_[k][e];
      for (int m = local(e, 0, 0); m < local(e, 0, 0) + nb_ * nb_; ++m) {
        Vector3d x = ref_.col(m);
        x[k] = -x[k];
        for (int q = local(f, 0, 0); q < local(f, 0, 0) + nb_ * nb_; ++q)
          if ((ref_.col(q) - x).norm() < kMatchTol) mirror_[k][m] = q;
        if (mirror_[k][m] < 0)
          throw std::logic_error("Mesh: node " + std::to_string(m) + " has no mirror image");
      }
    }
  }
}

}  // namespace capflow::geometry
