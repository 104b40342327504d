#include "diagnostics/diagnostics.h"

#include "geometry/element_search.h"
#include "spectral/spectral.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace capflow::diagnostics {

namespace {

using geometry::ElementEvaluator;
using geometry::SurfacePoint;

// The minimum of psi over the whole surface: the best node, then the element minimum
// (geometry::minimise_on_element) in every element sharing it.
double minimise(const Mesh& mesh, const Matrix3Xd& x, const ElementEvaluator& ev,
                const geometry::QuadraticOfPosition& psi) {
  int best = 0;
  double best_value = std::numeric_limits<double>::infinity();
  for (int m = 0; m < mesh.num_local(); ++m) {
    const double v = psi.value(x.col(m));
    if (v < best_value) {
      best_value = v;
      best = m;
    }
  }
  double result = best_value;
  const int nb = mesh.nb();
  for (int q : mesh.classes()[mesh.unique_of()[best]]) {
    const int e = q / (nb * nb);
    const int i = q % nb, j = (q / nb) % nb;
    result = std::min(
        result, geometry::minimise_on_element(ev, psi, e, mesh.nodes()[i], mesh.nodes()[j]).value);
  }
  return result;
}

// Solves y(s,t) = c1, z(s,t) = c2 on element e (2x2 Newton); false if it leaves the element.
bool pierce_x_axis(const ElementEvaluator& ev, int e, double s, double t, const Vector3d& c,
                   double* s_out, double* t_out) {
  for (int it = 0; it < 50; ++it) {
    const SurfacePoint p = ev.eval(e, s, t);
    const Eigen::Vector2d r(p.x.y() - c.y(), p.x.z() - c.z());
    Eigen::Matrix2d j;
    j << p.xs.y(), p.xt.y(), p.xs.z(), p.xt.z();
    if (std::abs(j.determinant()) < 1e-300) return false;
    const Eigen::Vector2d step = -j.inverse() * r;
    s += step[0];
    t += step[1];
    if (std::abs(s) > 1.5 || std::abs(t) > 1.5) return false;
    if (step.norm() < 1e-15) break;
  }
  *s_out = s;
  *t_out = t;
  return std::abs(s) <= 1.0 + 1e-9 && std::abs(t) <= 1.0 + 1e-9;
}

// How far p is from the +x axis through c, as the tangent of the angle; infinity behind c.
double axis_distance(const Vector3d& p, const Vector3d& c) {
  const Vector3d r = p - c;
  if (r.x() <= 0) return std::numeric_limits<double>::infinity();
  return std::hypot(r.y(), r.z()) / r.x();
}

// The node of element e closest to the +x axis through c (-1 if none lies in front of c).
int element_node_nearest_axis(const Mesh& mesh, const Matrix3Xd& x, const Vector3d& c, int e) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int j = 0; j < mesh.nb(); ++j)
    for (int i = 0; i < mesh.nb(); ++i) {
      const double d = axis_distance(x.col(mesh.local(e, i, j)), c);
      if (d < best_d) {
        best_d = d;
        best = j * mesh.nb() + i;
      }
    }
  return best;
}

// The crossing of the +x axis through c with element e, by Newton from the element's node
// closest to the axis: false if no node lies in front of c, Newton leaves the element or it
// converges behind c.
bool element_crossing(const Mesh& mesh, const Matrix3Xd& x, const ElementEvaluator& ev,
                      const Vector3d& c, int e, double* s, double* t) {
  const int q = element_node_nearest_axis(mesh, x, c, e), nb = mesh.nb();
  return q >= 0 && pierce_x_axis(ev, e, mesh.nodes()[q % nb], mesh.nodes()[q / nb], c, s, t) &&
         ev.eval(e, *s, *t).x.x() > c.x();
}

// The normal curvature along e_y (the tangent closest to it) at the surface point p.
double curvature_along_y(const SurfacePoint& p) {
  const Vector3d n = p.normal();
  Eigen::Matrix2d g;
  g << p.xs.dot(p.xs), p.xs.dot(p.xt), p.xs.dot(p.xt), p.xt.dot(p.xt);
  Eigen::Matrix2d b;
  b << n.dot(p.xss), n.dot(p.xst), n.dot(p.xst), n.dot(p.xtt);
  const Eigen::Vector2d d = g.inverse() * Eigen::Vector2d(p.xs.y(), p.xt.y());
  return std::abs(d.dot(b * d)) / d.dot(g * d);
}

// The edge curvature at the crossing of the +x axis through c: every element is searched from
// its own node closest to the axis (a crossing just across an element edge from the closest
// node of all is found in the neighbour), and the outermost crossing (largest x) is taken. NaN
// when no element holds a crossing (a surface the axis leaves through a gap, c outside the
// body).
double edge_curvature_at_tip(const Mesh& mesh, const Matrix3Xd& x, const ElementEvaluator& ev,
                             const Vector3d& c, Vector3d* tip) {
  bool found = false;
  SurfacePoint outer;
  for (int e = 0; e < mesh.ne(); ++e) {
    double s, t;
    if (!element_crossing(mesh, x, ev, c, e, &s, &t)) continue;
    const SurfacePoint p = ev.eval(e, s, t);
    if (!found || p.x.x() > outer.x.x()) outer = p;
    found = true;
  }
  if (!found) {
    *tip = c;
    return std::numeric_limits<double>::quiet_NaN();
  }
  *tip = outer.x;
  return curvature_along_y(outer);
}

void assign_axes(ShapeDiagnostics* r, AxesMode mode) {
  const Matrix3d& v = r->axis_directions;
  if (mode == AxesMode::FlowAxes) {
    // Greedy assignment by alignment |v_k . e_axis|, largest first.
    int owner[3] = {-1, -1, -1};  // flow axis -> eigen index
    bool used[3] = {false, false, false};
    for (int pass = 0; pass < 3; ++pass) {
      double best = -1;
      int bk = 0, ba = 0;
      for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a)
          if (!used[k] && owner[a] < 0 && std::abs(v(a, k)) > best) {
            best = std::abs(v(a, k));
            bk = k;
            ba = a;
          }
      used[bk] = true;
      owner[ba] = bk;
    }
    r->L = r->semi_axes[owner[0]];
    r->S = r->semi_axes[owner[1]];
    r->W = r->semi_axes[owner[2]];
  } else {
    int ky = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(v(1, k)) > std::abs(v(1, ky))) ky = k;
    int kl = -1, ks = -1;
    for (int k = 0; k < 3; ++k) {
      if (k == ky) continue;
      if (kl < 0)
        kl = k;
      else
        ks = k;
    }
    if (r->semi_axes[ks] > r->semi_axes[kl]) std::swap(kl, ks);
    r->L = r->semi_axes[kl];
    r->S = r->semi_axes[ks];
    r->W = r->semi_axes[ky];
    double ang = std::atan2(v(2, kl), v(0, kl)) * 180.0 / 3.14159265358979323846;
    if (ang > 90.0) ang -= 180.0;
    if (ang <= -90.0) ang += 180.0;
    r->inclination_deg = ang;
  }
  r->D = (r->L - r->S) / (r->L + r->S);
}

}  // namespace

ShapeDiagnostics measure_shape(const Mesh& mesh, const Matrix3Xd& x, const ShapeOptions& opt) {
  ShapeDiagnostics r;
  const int nq = opt.nq > 0 ? opt.nq : mesh.nb() + 4;
  const geometry::QuadratureSurface q = geometry::sample_gauss(mesh, x, nq);
  const int n = static_cast<int>(q.x.cols());
  Vector3d cnum = Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    r.area += q.w[k];
    r.volume += q.x.col(k).dot(q.n.col(k)) * q.w[k] / 3.0;
    cnum += 0.5 * q.x.col(k).squaredNorm() * q.n.col(k) * q.w[k];
  }
  r.centroid = cnum / r.volume;
  for (int k = 0; k < n; ++k) {
    const Vector3d xi = q.x.col(k) - r.centroid;
    r.inertia += xi * xi.transpose() * (xi.dot(q.n.col(k)) * q.w[k] / 5.0);
  }
  Eigen::SelfAdjointEigenSolver<Matrix3d> es(r.inertia);
  // Eigen sorts ascending; store descending.
  for (int k = 0; k < 3; ++k) {
    r.semi_axes[k] = std::sqrt(5.0 * std::max(0.0, es.eigenvalues()[2 - k]) / r.volume);
    r.axis_directions.col(k) = es.eigenvectors().col(2 - k);
  }
  assign_axes(&r, opt.axes);

  const ElementEvaluator ev(mesh, x);
  if (opt.extrema) {
    const Vector3d c = r.centroid;
    // farthest point (a = -1), nearest point (a = 1), highest and lowest z (linear)
    const geometry::QuadraticOfPosition far{-1.0, c, Vector3d::Zero()};
    const geometry::QuadraticOfPosition near{1.0, c, Vector3d::Zero()};
    const geometry::QuadraticOfPosition up{0.0, c, Vector3d(0, 0, -1)};
    const geometry::QuadraticOfPosition down{0.0, c, Vector3d(0, 0, 1)};
    r.Lc = std::sqrt(-2.0 * minimise(mesh, x, ev, far));
    r.Sc = std::sqrt(2.0 * minimise(mesh, x, ev, near));
    r.Wc = std::max(-minimise(mesh, x, ev, up) - c.z(), c.z() - minimise(mesh, x, ev, down));
  }
  if (opt.edge_curvature) r.edge_curvature = edge_curvature_at_tip(mesh, x, ev, r.centroid, &r.tip);
  return r;
}

std::vector<Vector2d> cross_section(const Mesh& mesh, const Matrix3Xd& x, int axis, double value,
                                    const Vector2d& center) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("cross_section: axis must be 0, 1 or 2");
  const int a0 = (axis == 0) ? 1 : 0;
  const int a1 = (axis == 2) ? 1 : 2;
  const ElementEvaluator ev(mesh, x);
  const int nb = mesh.nb(), nb2 = nb * nb;
  const int lines = 4 * nb;
  const int samples = 4 * nb;
  // The scan for sign changes works on one coordinate along 1-D lines: the element's nodal
  // x[axis] interpolated across to the line (Lc: the bases at the line's fixed coordinate), then
  // along it at the samples (Ls: the bases at u_k = -1 + 2k/samples, shared by every line); only
  // the bracketed roots are refined with the full 2-D evaluation.
  const Eigen::VectorXd& nodes = mesh.nodes();
  const Eigen::VectorXd bw = spectral::barycentric_weights(nodes);
  Eigen::MatrixXd Ls(samples + 1, nb), Lc(nb, lines);
  std::vector<double> basis(nb);
  for (int k = 0; k <= samples; ++k) {
    spectral::lagrange_basis(nodes, bw, -1.0 + 2.0 * k / samples, basis.data(), nullptr);
    for (int j = 0; j < nb; ++j) Ls(k, j) = basis[j];
  }
  for (int c = 0; c < lines; ++c)
    spectral::lagrange_basis(nodes, bw, -1.0 + 2.0 * (c + 0.5) / lines, Lc.col(c).data(), nullptr);
  Eigen::MatrixXd X(nb, nb), G(nb, lines), F(samples + 1, lines);
  std::vector<Vector2d> pts;
  for (int e = 0; e < mesh.ne(); ++e) {
    for (int j = 0; j < nb; ++j)
      for (int i = 0; i < nb; ++i) X(i, j) = x(axis, e * nb2 + j * nb + i);  // i along s
    for (int dir = 0; dir < 2; ++dir) {
      // dir 0: s fixed, t = u varies; dir 1: t fixed, s = u varies
      if (dir == 0)
        G.noalias() = X.transpose() * Lc;  // G(j, l) = x along t_j at s_l
      else
        G.noalias() = X * Lc;  // G(i, l) = x along s_i at t_l
      F.noalias() = Ls * G;
      for (int l = 0; l < lines; ++l) {
        const double fixed = -1.0 + 2.0 * (l + 0.5) / lines;
        auto at = [&](double u) { return dir == 0 ? ev.eval(e, fixed, u) : ev.eval(e, u, fixed); };
        double u_prev = -1.0;
        double f_prev = F(0, l) - value;
        for (int k = 1; k <= samples; ++k) {
          const double u = -1.0 + 2.0 * k / samples;
          const double f = F(k, l) - value;
          if ((f_prev <= 0 && f > 0) || (f_prev > 0 && f <= 0)) {
            // Safeguarded Newton (falls back to bisection) on [u_prev, u].
            double lo = u_prev, hi = u, flo = f_prev;
            double r = 0.5 * (lo + hi);
            for (int it = 0; it < 60; ++it) {
              const SurfacePoint p = at(r);
              const double fr = p.x[axis] - value;
              if (std::abs(fr) < 1e-14) break;
              if ((fr > 0) == (flo > 0)) {
                lo = r;
                flo = fr;
              } else {
                hi = r;
              }
              const double dfr = (dir == 0 ? p.xt : p.xs)[axis];
              double rn = (dfr != 0) ? r - fr / dfr : 0.5 * (lo + hi);
              if (rn <= lo || rn >= hi) rn = 0.5 * (lo + hi);
              if (std::abs(rn - r) < 1e-15) break;
              r = rn;
            }
            const Vector3d p = at(r).x;
            pts.emplace_back(p[a0], p[a1]);
          }
          u_prev = u;
          f_prev = f;
        }
      }
    }
  }
  std::sort(pts.begin(), pts.end(), [&center](const Vector2d& a, const Vector2d& b) {
    return std::atan2(a.y() - center.y(), a.x() - center.x()) <
           std::atan2(b.y() - center.y(), b.x() - center.x());
  });
  return pts;
}

}  // namespace capflow::diagnostics
