#include "geometry/element_search.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace capflow::geometry {

using Eigen::Vector3d;

ElementMinimum minimise_on_element(const ElementEvaluator& ev, const QuadraticOfPosition& psi,
                                   int e, double s, double t) {
  constexpr double kSlack = 64.0 * std::numeric_limits<double>::epsilon();
  SurfacePoint p = ev.eval(e, s, t);
  double f = psi.value(p.x);
  for (int it = 0; it < 50; ++it) {
    const Vector3d gx = psi.grad(p.x);
    const double g1 = p.xs.dot(gx), g2 = p.xt.dot(gx);
    const bool fs = !((s <= -1.0 && g1 > 0.0) || (s >= 1.0 && g1 < 0.0));
    const bool ft = !((t <= -1.0 && g2 > 0.0) || (t >= 1.0 && g2 < 0.0));
    if (!fs && !ft) break;  // a corner satisfying the optimality conditions
    // metric used where the Hessian is not positive definite
    const double m = psi.a > 0.0 ? psi.a : 1.0;
    double h11 = psi.a * p.xs.squaredNorm() + p.xss.dot(gx);
    double h12 = psi.a * p.xs.dot(p.xt) + p.xst.dot(gx);
    double h22 = psi.a * p.xt.squaredNorm() + p.xtt.dot(gx);
    double ds = 0, dt = 0;
    if (fs && ft) {
      double det = h11 * h22 - h12 * h12;
      if (!(h11 > 0.0 && det > 0.0)) {
        h11 = m * p.xs.squaredNorm();
        h12 = m * p.xs.dot(p.xt);
        h22 = m * p.xt.squaredNorm();
        det = h11 * h22 - h12 * h12;
      }
      ds = -(h22 * g1 - h12 * g2) / det;
      dt = -(-h12 * g1 + h11 * g2) / det;
    } else if (fs) {
      ds = -g1 / (h11 > 0.0 ? h11 : m * p.xs.squaredNorm());
    } else {
      dt = -g2 / (h22 > 0.0 ? h22 : m * p.xt.squaredNorm());
    }
    double sn = s, tn = t, fn = f;
    SurfacePoint pn;
    bool improved = false;
    for (int half = 0; half < 30; ++half) {
      sn = std::clamp(s + ds, -1.0, 1.0);
      tn = std::clamp(t + dt, -1.0, 1.0);
      pn = ev.eval(e, sn, tn);
      fn = psi.value(pn.x);
      // Near the minimum f changes by O(step^2), below its rounding once the step is ~1e-8:
      // a step that raises f by no more than the rounding is taken, so Newton converges in
      // position instead of stopping where f stops resolving the change (kSlack: the rounding of
      // f through the interpolation, tens of ulps; 8 ulps stopped at 1e-9 with FMA contraction)
      if (fn <= f + kSlack * std::abs(f)) {
        improved = true;
        break;
      }
      ds *= 0.5;
      dt *= 0.5;
    }
    if (!improved) break;
    const double step = std::abs(sn - s) + std::abs(tn - t);
    s = sn;
    t = tn;
    p = pn;
    f = fn;
    if (step < 1e-13) break;
  }
  return {s, t, p, f};
}

double nearest_node(const Mesh& mesh, const Eigen::Matrix3Xd& x, int e, const Vector3d& x0,
                    int* node) {
  const int nb2 = mesh.nb() * mesh.nb(), base = e * nb2;
  double d2 = 1e300;
  int best = 0;
  for (int k = 0; k < nb2; ++k) {
    const double dk = (x.col(base + k) - x0).squaredNorm();
    if (dk < d2) {
      d2 = dk;
      best = k;
    }
  }
  if (node) *node = best;
  return std::sqrt(d2);
}

NearestPoint nearest_point(const Mesh& mesh, const Eigen::Matrix3Xd& x, int e, const Vector3d& x0,
                           int start_node) {
  const int nb = mesh.nb();
  int best = start_node;
  if (best < 0) nearest_node(mesh, x, e, x0, &best);
  const ElementEvaluator ev(mesh, x);
  QuadraticOfPosition psi;
  psi.c = x0;
  const ElementMinimum m =
      minimise_on_element(ev, psi, e, mesh.nodes()[best % nb], mesh.nodes()[best / nb]);
  return {m.s, m.t, (m.p.x - x0).norm(), m.p.xs, m.p.xt};
}

}  // namespace capflow::geometry
