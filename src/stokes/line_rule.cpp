#include "stokes/line_rule.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace capflow::stokes {

using Eigen::VectorXd;

namespace {

void radial_nodes(double h, const spectral::Rule& gr, const RadialOpt& ro,
                  std::vector<std::pair<double, double>>& rad) {
  rad.clear();
  if (h <= 0.0) {
    for (int b = 0; b < gr.x.size(); ++b) rad.emplace_back(0.5 * (gr.x[b] + 1.0), 0.5 * gr.w[b]);
    return;
  }
  const spectral::Rule& gi = ro.gi ? *ro.gi : gr;
  const double u1 = ro.split > 0.0 ? std::min(1.0, ro.split) : 1.0;
  const double sig_max = std::asinh(u1 / h);
  constexpr double kPanel = 6.0;
  const int panels = std::max(1, static_cast<int>(std::ceil(sig_max / kPanel)));
  const double dsig = sig_max / panels;
  for (int pan = 0; pan < panels; ++pan)
    for (int b = 0; b < gi.x.size(); ++b) {
      const double sig = dsig * (pan + 0.5 * (gi.x[b] + 1.0));
      rad.emplace_back(h * std::sinh(sig), 0.5 * dsig * gi.w[b] * h * std::cosh(sig));
    }
  if (u1 < 1.0) {
    const spectral::Rule& go = ro.go ? *ro.go : gr;
    const int np = std::max(1, ro.out_panels);
    double len = (1 - u1) / ((1 << np) - 1), a = u1;  // lengths len, 2 len, 4 len, ...
    for (int q = 0; q < np; ++q, a += len, len *= 2)
      for (int b = 0; b < go.x.size(); ++b)
        rad.emplace_back(a + 0.5 * len * (go.x[b] + 1.0), 0.5 * len * go.w[b]);
  }
}

}  // namespace

void polar_rule(double s0, double t0, const double* hu, const spectral::Rule& ge,
                const spectral::Rule& gr, LineRule& R, const RadialOpt& ro,
                const std::function<const spectral::Rule&(double)>* edge_rule) {
  R.c.clear();
  R.start.assign(1, 0);
  R.base.clear();
  R.scale.clear();
  R.wscale.clear();
  R.set.clear();
  R.edge.clear();
  R.radial.clear();
  R.set_start.assign(1, 0);
  R.off.clear();
  R.wedge.clear();
  R.n0 = -1;
  struct Edge {
    double fs, ft, d;
    int axis;       // 0: edge runs along s, 1: along t
    double lo, hi;  // lengths from the foot towards -, + along the edge
  };
  const Edge edges[4] = {
      {-1.0, t0, s0 + 1.0, 1, t0 + 1.0, 1.0 - t0},
      {1.0, t0, 1.0 - s0, 1, t0 + 1.0, 1.0 - t0},
      {s0, -1.0, t0 + 1.0, 0, s0 + 1.0, 1.0 - s0},
      {s0, 1.0, 1.0 - t0, 0, s0 + 1.0, 1.0 - s0},
  };
  constexpr double kTiny = 1e-14;
  std::vector<std::pair<double, double>> rad;
  for (int ei = 0; ei < 4; ++ei) {
    if (ei == 2) R.n0 = static_cast<int>(R.c.size());
    const Edge& E = edges[ei];
    if (E.d < kTiny) continue;
    const double h = hu[ei];
    radial_nodes(h, gr, ro, rad);
    // coordinate along the edge of the foot and of p0 (the same), and across
    const double p_along = E.axis == 1 ? t0 : s0;
    const double p_across = E.axis == 1 ? s0 : t0;
    const double f_across = E.axis == 1 ? E.fs : E.ft;
    // the edge point set: along-edge offsets from the foot, times the Jacobian weight, side
    // k = 0 (towards -) then k = 1
    for (int k = 0; k < 2; ++k) {
      const double L = k == 0 ? E.lo : E.hi;
      if (L < kTiny) continue;
      const double tau_max = std::asinh(L / E.d);
      const double dir = k == 0 ? -1.0 : 1.0;
      const spectral::Rule& gs = edge_rule ? (*edge_rule)(tau_max) : ge;
      for (int a = 0; a < static_cast<int>(gs.x.size()); ++a) {
        const double tau = 0.5 * tau_max * (gs.x[a] + 1.0);
        const double wt = 0.5 * tau_max * gs.w[a];
        R.off.push_back(dir * E.d * std::sinh(tau));
        R.wedge.push_back(wt * E.d * std::cosh(tau) * E.d);
      }
    }
    const int set = static_cast<int>(R.set_start.size()) - 1;
    R.set_start.push_back(static_cast<int>(R.off.size()));
    const int m = R.set_start[set + 1] - R.set_start[set];
    for (int q = 0; q < static_cast<int>(rad.size()); ++q) {
      const double u = rad[q].first, wu = rad[q].second;
      R.edge.push_back(ei);
      R.radial.push_back(q);
      R.c.push_back(p_across + u * (f_across - p_across));
      R.base.push_back(p_along);
      R.scale.push_back(u);
      R.wscale.push_back(u * wu);
      R.set.push_back(set);
      R.start.push_back(R.start.back() + m);
    }
  }
}

void fill_bases(const geometry::Mesh& mesh, const VectorXd& prod_w, LineRule& R) {
  const int nb = mesh.nb(), nl = R.nl();
  if (R.Lc.rows() != nb || R.Lc.cols() < nl) {
    R.Lc.resize(nb, nl);
    R.dLc.resize(nb, nl);
  }
  // all lines at once (vectorised over the lines, spectral::lagrange_bases), then transposed to
  // one column per line as stage 1 reads them
  thread_local Eigen::MatrixXd L, dL;
  if (L.rows() < nl || L.cols() != nb) {
    L.resize(std::max<Eigen::Index>(nl, L.rows()), nb);
    dL.resize(L.rows(), nb);
  }
  spectral::lagrange_bases(mesh.nodes(), prod_w, R.c.data(), nl, L.data(), dL.data(), L.rows());
  for (int l = 0; l < nl; ++l)
    for (int j = 0; j < nb; ++j) {
      R.Lc(j, l) = L(l, j);
      R.dLc(j, l) = dL(l, j);
    }
}

}  // namespace capflow::stokes
