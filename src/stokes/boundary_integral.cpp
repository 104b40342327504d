#include "stokes/boundary_integral.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "geometry/surface.h"
#include "spectral/spectral.h"

namespace capflow::stokes {

using Eigen::Vector3d;
using Eigen::VectorXd;
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

namespace {

constexpr int kMaxNb = 64;

// Perpendicular/sinh polar rule around p0 = (s0, t0) in [-1,1]^2 (see the header). hc = 0:
// plain Gauss along each ray (own element); hc > 0: radial sinh map with scale hc (param units).
void polar_rule(double s0, double t0, double hc, const spectral::Rule& ge,
                const spectral::Rule& gr, std::vector<double>& S, std::vector<double>& T,
                std::vector<double>& W) {
  S.clear();
  T.clear();
  W.clear();
  // Edges: (foot, perpendicular distance, edge direction axis).
  struct Edge {
    double fs, ft, d;
    int axis;  // 0: edge runs along s, 1: along t
    double lo, hi;  // lengths from the foot towards -, + along the edge
  };
  const Edge edges[4] = {
      {-1.0, t0, s0 + 1.0, 1, t0 + 1.0, 1.0 - t0},
      {1.0, t0, 1.0 - s0, 1, t0 + 1.0, 1.0 - t0},
      {s0, -1.0, t0 + 1.0, 0, s0 + 1.0, 1.0 - s0},
      {s0, 1.0, 1.0 - t0, 0, s0 + 1.0, 1.0 - s0},
  };
  constexpr double kTiny = 1e-14;
  constexpr double kPanel = 6.0;
  for (const Edge& E : edges) {
    if (E.d < kTiny) continue;
    for (int dir = -1; dir <= 1; dir += 2) {
      const double L = dir < 0 ? E.lo : E.hi;
      if (L < kTiny) continue;
      const double tau_max = std::asinh(L / E.d);
      for (int a = 0; a < ge.x.size(); ++a) {
        const double tau = 0.5 * tau_max * (ge.x[a] + 1.0);
        const double wt = 0.5 * tau_max * ge.w[a];
        const double sv = E.d * std::sinh(tau);
        const double js = E.d * std::cosh(tau);
        const double ps = E.axis == 0 ? E.fs + dir * sv : E.fs;
        const double pt = E.axis == 1 ? E.ft + dir * sv : E.ft;
        const double as = ps - s0, at = pt - t0;
        const double ell = std::sqrt(as * as + at * at);
        // Radial sinh map: sigma in [0, asinh(l/hc)], split into panels of length <= kPanel
        // (the integrand grows like e^sigma, so very small hc needs more than one panel).
        const double sig_max = hc > 0.0 ? std::asinh(ell / hc) : 0.0;
        const int panels = hc > 0.0 ? std::max(1, static_cast<int>(std::ceil(sig_max / kPanel))) : 1;
        const double dsig = sig_max / panels;
        for (int pan = 0; pan < panels; ++pan)
          for (int b = 0; b < gr.x.size(); ++b) {
            double u, wu;
            if (hc <= 0.0) {
              u = 0.5 * (gr.x[b] + 1.0);
              wu = 0.5 * gr.w[b];
            } else {
              const double sig = dsig * (pan + 0.5 * (gr.x[b] + 1.0));
              u = (hc / ell) * std::sinh(sig);
              wu = 0.5 * dsig * gr.w[b] * (hc / ell) * std::cosh(sig);
            }
            S.push_back(s0 + u * as);
            T.push_back(t0 + u * at);
            W.push_back(wt * js * E.d * u * wu);
          }
      }
    }
  }
}

void fill_bases(const geometry::Mesh& mesh, const double* s, const double* t, int np,
                MatrixXd& ls, MatrixXd& dls, MatrixXd& lt, MatrixXd& dlt) {
  for (int p = 0; p < np; ++p) {
    spectral::lagrange_basis(mesh.nodes(), mesh.bary(), s[p], ls.col(p).data(),
                             dls.col(p).data());
    spectral::lagrange_basis(mesh.nodes(), mesh.bary(), t[p], lt.col(p).data(),
                             dlt.col(p).data());
  }
}

// Value, first and second derivatives of one element's interpolant at (s, t).
struct Eval2 {
  Vector3d x, xs, xt, xss, xst, xtt;
};
Eval2 eval2(const geometry::Mesh& mesh, const Matrix3Xd& x, int e, double s, double t) {
  const int nb = mesh.nb();
  double ls[kMaxNb], dls[kMaxNb], lt[kMaxNb], dlt[kMaxNb], d2s[kMaxNb], d2t[kMaxNb];
  spectral::lagrange_basis(mesh.nodes(), mesh.bary(), s, ls, dls);
  spectral::lagrange_basis(mesh.nodes(), mesh.bary(), t, lt, dlt);
  const MatrixXd& D = mesh.diff();
  for (int i = 0; i < nb; ++i) {
    d2s[i] = 0.0;
    d2t[i] = 0.0;
    for (int k = 0; k < nb; ++k) {
      d2s[i] += dls[k] * D(k, i);
      d2t[i] += dlt[k] * D(k, i);
    }
  }
  Eval2 r;
  r.x.setZero();
  r.xs.setZero();
  r.xt.setZero();
  r.xss.setZero();
  r.xst.setZero();
  r.xtt.setZero();
  const int base = e * nb * nb;
  for (int j = 0; j < nb; ++j) {
    Vector3d c0 = Vector3d::Zero(), c1 = Vector3d::Zero(), c2 = Vector3d::Zero();
    for (int i = 0; i < nb; ++i) {
      const Vector3d xi = x.col(base + j * nb + i);
      c0 += ls[i] * xi;
      c1 += dls[i] * xi;
      c2 += d2s[i] * xi;
    }
    r.x += lt[j] * c0;
    r.xs += lt[j] * c1;
    r.xt += dlt[j] * c0;
    r.xss += lt[j] * c2;
    r.xst += dlt[j] * c1;
    r.xtt += d2t[j] * c0;
  }
  return r;
}

// Nearest point of element e to x0 (Newton from the nearest node, clipped to the square).
void nearest_point(const geometry::Mesh& mesh, const Matrix3Xd& x, int e, const Vector3d& x0,
                   double& s, double& t, double& h, double& c) {
  const int nb = mesh.nb();
  const int base = e * nb * nb;
  int best = 0;
  double bd = 1e300;
  for (int k = 0; k < nb * nb; ++k) {
    const double d = (x.col(base + k) - x0).squaredNorm();
    if (d < bd) {
      bd = d;
      best = k;
    }
  }
  s = mesh.nodes()[best % nb];
  t = mesh.nodes()[best / nb];
  Eval2 p = eval2(mesh, x, e, s, t);
  for (int it = 0; it < 30; ++it) {
    const Vector3d r = p.x - x0;
    const double g1 = p.xs.dot(r), g2 = p.xt.dot(r);
    double h11 = p.xs.squaredNorm() + p.xss.dot(r);
    double h12 = p.xs.dot(p.xt) + p.xst.dot(r);
    double h22 = p.xt.squaredNorm() + p.xtt.dot(r);
    double det = h11 * h22 - h12 * h12;
    if (!(h11 > 0.0 && det > 0.0)) {  // fall back to Gauss-Newton
      h11 = p.xs.squaredNorm();
      h12 = p.xs.dot(p.xt);
      h22 = p.xt.squaredNorm();
      det = h11 * h22 - h12 * h12;
    }
    const double ds = -(h22 * g1 - h12 * g2) / det;
    const double dt = -(-h12 * g1 + h11 * g2) / det;
    const double sn = std::clamp(s + ds, -1.0, 1.0), tn = std::clamp(t + dt, -1.0, 1.0);
    const double step = std::abs(sn - s) + std::abs(tn - t);
    s = sn;
    t = tn;
    p = eval2(mesh, x, e, s, t);
    if (step < 1e-13) break;
  }
  h = (p.x - x0).norm();
  c = std::sqrt(p.xs.norm() * p.xt.norm());
}

// Far-field data at the Gauss points, row-major rows:
// 0-2 x, 3-5 density (Single: times w J), 6-8 w (x_xi x x_eta), 9 w J.
struct FarData {
  int nq = 0;
  RowMat d;
  std::vector<Vector3d> centre;
  std::vector<double> radius, size;
};

template <BoundaryOperators::Mode M>
inline void kernel(const Vector3d& x0, const Vector3d& u0, double px, double py, double pz,
                   const double* dens, const double* nw, double wj, double* acc) {
  using Mode = BoundaryOperators::Mode;
  const double rx = px - x0[0], ry = py - x0[1], rz = pz - x0[2];
  const double r2 = rx * rx + ry * ry + rz * rz;
  const double ir = 1.0 / std::sqrt(r2);
  const double ir3 = ir * ir * ir;
  if constexpr (M == Mode::Single) {
    const double rd = rx * dens[0] + ry * dens[1] + rz * dens[2];
    const double a = wj * ir, b = wj * rd * ir3;
    acc[0] += a * dens[0] + b * rx;
    acc[1] += a * dens[1] + b * ry;
    acc[2] += a * dens[2] + b * rz;
  } else if constexpr (M == Mode::SingleNormal) {
    const double rn = rx * nw[0] + ry * nw[1] + rz * nw[2];
    const double b = rn * ir3;
    acc[0] += ir * nw[0] + b * rx;
    acc[1] += ir * nw[1] + b * ry;
    acc[2] += ir * nw[2] + b * rz;
  } else if constexpr (M == Mode::Double) {
    const double qx = dens[0] - u0[0], qy = dens[1] - u0[1], qz = dens[2] - u0[2];
    const double rq = rx * qx + ry * qy + rz * qz;
    const double rn = rx * nw[0] + ry * nw[1] + rz * nw[2];
    const double a = -6.0 * rq * rn * ir3 * ir * ir;
    acc[0] += a * rx;
    acc[1] += a * ry;
    acc[2] += a * rz;
  } else {
    const double rn = rx * nw[0] + ry * nw[1] + rz * nw[2];
    const double a = -6.0 * rn * ir3 * ir * ir;
    const double r[3] = {rx, ry, rz};
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) acc[i + 3 * j] += a * r[i] * r[j];
  }
}

constexpr bool uses_density(BoundaryOperators::Mode m) {
  return m == BoundaryOperators::Mode::Single || m == BoundaryOperators::Mode::Double;
}

struct Scratch {
  MatrixXd P, M, Md, ls, dls, lt, dlt;
  std::vector<double> s, t, w;
  std::vector<int> near_e;
  std::vector<double> near_s, near_t, near_hc;
};

// Sum the kernel over the points of one special rule. P: nb x (K nb) element data in the
// rule's orientation; sign: orientation of the rule's (s, t) relative to the element's.
template <BoundaryOperators::Mode M>
void special_sum(int nb, const MatrixXd& P, int K, const MatrixXd& ls, const MatrixXd& dls,
                 const MatrixXd& lt, const MatrixXd& dlt, const double* w, int np, double sign,
                 const Vector3d& x0, const Vector3d& u0, Scratch& sc, double* acc) {
  sc.M.topLeftCorner(K * nb, np).noalias() = P.leftCols(K * nb).transpose() * ls.leftCols(np);
  sc.Md.topLeftCorner(3 * nb, np).noalias() = P.leftCols(3 * nb).transpose() * dls.leftCols(np);
  for (int p = 0; p < np; ++p) {
    const double* m = sc.M.col(p).data();
    const double* md = sc.Md.col(p).data();
    const double* l = lt.col(p).data();
    const double* dl = dlt.col(p).data();
    double xv[3], xs[3], xt[3], dv[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      double a = 0, b = 0, c = 0;
      for (int j = 0; j < nb; ++j) {
        a += m[k * nb + j] * l[j];
        b += md[k * nb + j] * l[j];
        c += m[k * nb + j] * dl[j];
      }
      xv[k] = a;
      xs[k] = b;
      xt[k] = c;
    }
    if constexpr (uses_density(M)) {
      for (int k = 0; k < 3; ++k) {
        double a = 0;
        for (int j = 0; j < nb; ++j) a += m[(3 + k) * nb + j] * l[j];
        dv[k] = a;
      }
    }
    double nw[3] = {sign * (xs[1] * xt[2] - xs[2] * xt[1]), sign * (xs[2] * xt[0] - xs[0] * xt[2]),
                    sign * (xs[0] * xt[1] - xs[1] * xt[0])};
    const double jac = std::sqrt(nw[0] * nw[0] + nw[1] * nw[1] + nw[2] * nw[2]);
    for (double& v : nw) v *= w[p];
    kernel<M>(x0, u0, xv[0], xv[1], xv[2], dv, nw, w[p] * jac, acc);
  }
}

}  // namespace

BoundaryOperators::BoundaryOperators(const geometry::Mesh& mesh, QuadratureOptions options)
    : mesh_(mesh), opt_(options) {
  const int nb = mesh.nb();
  if (nb > kMaxNb) throw std::invalid_argument("BoundaryOperators: nb too large");
  if (opt_.nq_far <= 0) opt_.nq_far = nb + 3;
  if (opt_.n_edge <= 0) opt_.n_edge = 2 * nb;
  if (opt_.n_radial <= 0) opt_.n_radial = nb + 2;
  if (opt_.n_edge_near <= 0) opt_.n_edge_near = nb + 2;
  if (opt_.n_radial_near <= 0) opt_.n_radial_near = 2 * nb - 4;
  const spectral::Rule ge = spectral::gauss_legendre(opt_.n_edge);
  const spectral::Rule gr = spectral::gauss_legendre(opt_.n_radial);
  const VectorXd& xi = mesh.nodes();
  canon_rule_.assign(nb * nb, -1);
  canon_sym_.assign(nb * nb, 0);
  std::map<int, int> key_to_rule;
  for (int j = 0; j < nb; ++j)
    for (int i = 0; i < nb; ++i) {
      const bool fi = 2 * i > nb - 1, fj = 2 * j > nb - 1;
      const int i1 = fi ? nb - 1 - i : i, j1 = fj ? nb - 1 - j : j;
      const bool sw = i1 > j1;
      const int ic = sw ? j1 : i1, jc = sw ? i1 : j1;
      const int key = ic + nb * jc;
      auto it = key_to_rule.find(key);
      if (it == key_to_rule.end()) {
        Rule r;
        polar_rule(xi[ic], xi[jc], 0.0, ge, gr, r.s, r.t, r.w);
        const int np = static_cast<int>(r.s.size());
        r.ls.resize(nb, np);
        r.dls.resize(nb, np);
        r.lt.resize(nb, np);
        r.dlt.resize(nb, np);
        fill_bases(mesh, r.s.data(), r.t.data(), np, r.ls, r.dls, r.lt, r.dlt);
        it = key_to_rule.emplace(key, static_cast<int>(rules_.size())).first;
        rules_.push_back(std::move(r));
      }
      canon_rule_[i + nb * j] = it->second;
      canon_sym_[i + nb * j] = (fi ? 1 : 0) | (fj ? 2 : 0) | (sw ? 4 : 0);
    }
  canon_perm_.assign(8, std::vector<int>(nb * nb));
  for (int sym = 0; sym < 8; ++sym)
    for (int b = 0; b < nb; ++b)
      for (int a = 0; a < nb; ++a) {
        const int al = (sym & 4) ? b : a, be = (sym & 4) ? a : b;
        const int i = (sym & 1) ? nb - 1 - al : al, j = (sym & 2) ? nb - 1 - be : be;
        canon_perm_[sym][a + nb * b] = i + nb * j;
      }
}

long BoundaryOperators::own_rule_points() const {
  long n = 0;
  for (const Rule& r : rules_) n += static_cast<long>(r.s.size());
  return n;
}

template <BoundaryOperators::Mode M>
void BoundaryOperators::apply(const Matrix3Xd& x, const Matrix3Xd* dens,
                              const std::vector<int>* node_targets,
                              const Matrix3Xd* point_targets, MatrixXd& out) const {
  const geometry::Mesh& mesh = mesh_;
  const int nb = mesh.nb(), nb2 = nb * nb, ne = mesh.ne();
  const int nloc = mesh.num_local();
  if (x.cols() != nloc) throw std::invalid_argument("BoundaryOperators: x has wrong size");
  if (uses_density(M) && (!dens || dens->cols() != nloc))
    throw std::invalid_argument("BoundaryOperators: density has wrong size");
  const int ntar = node_targets ? static_cast<int>(node_targets->size())
                                : static_cast<int>(point_targets->cols());
  if (node_targets)
    for (int m : *node_targets)
      if (m < 0 || m >= nloc) throw std::invalid_argument("BoundaryOperators: bad target index");
  constexpr int acc_rows = (M == Mode::DoubleNormal) ? 9 : 3;
  out.resize(acc_rows, ntar);
  constexpr int K = uses_density(M) ? 6 : 3;

  // ---- far-field data at Gauss points (per call: depends on the geometry) ----
  const int nq = opt_.nq_far;
  const spectral::Rule gq = spectral::gauss_legendre(nq);
  const MatrixXd I = spectral::interpolation_matrix(mesh.nodes(), gq.x);
  const MatrixXd Id = spectral::derivative_matrix(mesh.nodes(), gq.x);
  const int nqe = nq * nq;
  RowMat F(10, ne * nqe);
  std::vector<Vector3d> centre(ne);
  std::vector<double> radius(ne), esize(ne);
  {
    MatrixXd X(nb, nb), Q(nq, nq);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic> xq[3], xsq[3], xtq[3], dq[3];
    for (int e = 0; e < ne; ++e) {
      for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < nb; ++j)
          for (int i = 0; i < nb; ++i) X(i, j) = x(k, e * nb2 + j * nb + i);
        xq[k] = I * X * I.transpose();
        xsq[k] = Id * X * I.transpose();
        xtq[k] = I * X * Id.transpose();
        if (uses_density(M)) {
          for (int j = 0; j < nb; ++j)
            for (int i = 0; i < nb; ++i) X(i, j) = (*dens)(k, e * nb2 + j * nb + i);
          dq[k] = I * X * I.transpose();
        }
      }
      double area = 0;
      for (int b = 0; b < nq; ++b)
        for (int a = 0; a < nq; ++a) {
          const int q = e * nqe + b * nq + a;
          const Vector3d xs(xsq[0](a, b), xsq[1](a, b), xsq[2](a, b));
          const Vector3d xt(xtq[0](a, b), xtq[1](a, b), xtq[2](a, b));
          const Vector3d c = xs.cross(xt);
          const double w = gq.w[a] * gq.w[b];
          const double wj = w * c.norm();
          area += wj;
          for (int k = 0; k < 3; ++k) {
            F(k, q) = xq[k](a, b);
            F(6 + k, q) = w * c[k];
            if (uses_density(M)) F(3 + k, q) = dq[k](a, b);
            else F(3 + k, q) = 0.0;
          }
          F(9, q) = wj;
        }
      esize[e] = std::sqrt(area);
      Vector3d cen = x.middleCols(e * nb2, nb2).rowwise().mean();
      double rad = 0;
      for (int k = 0; k < nb2; ++k) rad = std::max(rad, (x.col(e * nb2 + k) - cen).norm());
      centre[e] = cen;
      radius[e] = rad;
    }
  }

  const spectral::Rule gen = spectral::gauss_legendre(opt_.n_edge_near);
  const spectral::Rule grn = spectral::gauss_legendre(opt_.n_radial_near);
  // up to 8 triangles; radial panels: asinh(l/hc) <= asinh(3/1e-14) < 6 * 6
  const int max_near_pts = 8 * opt_.n_edge_near * opt_.n_radial_near * 6;
  int max_own_pts = 0;
  for (const Rule& r : rules_) max_own_pts = std::max(max_own_pts, static_cast<int>(r.s.size()));
  const int max_pts = std::max(max_near_pts, max_own_pts);

  long far_pairs = 0, own_pairs = 0, near_pairs = 0, near_elements = 0;
#pragma omp parallel reduction(+ : far_pairs, own_pairs, near_pairs, near_elements)
  {
    Scratch sc;
    sc.P.resize(nb, 6 * nb);
    sc.M.resize(6 * nb, max_pts);
    sc.Md.resize(3 * nb, max_pts);
    sc.ls.resize(nb, max_near_pts);
    sc.dls.resize(nb, max_near_pts);
    sc.lt.resize(nb, max_near_pts);
    sc.dlt.resize(nb, max_near_pts);
    sc.s.reserve(max_near_pts);
    sc.t.reserve(max_near_pts);
    sc.w.reserve(max_near_pts);
    std::vector<char> own(ne);
    const double* Fx = F.row(0).data();
    const double* Fy = F.row(1).data();
    const double* Fz = F.row(2).data();

#pragma omp for schedule(dynamic, 4)
    for (int k = 0; k < ntar; ++k) {
      double acc[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
      Vector3d x0, u0 = Vector3d::Zero();
      std::fill(own.begin(), own.end(), 0);
      if (node_targets) {
        const int m = (*node_targets)[k];
        x0 = x.col(m);
        if (M == Mode::Double) u0 = dens->col(m);
        // own elements: every member of the coincidence class
        for (int q : mesh.classes()[mesh.unique_of()[m]]) {
          const int e = q / nb2, loc = q % nb2;
          own[e] = 1;
          const Rule& r = rules_[canon_rule_[loc]];
          const int sym = canon_sym_[loc];
          const std::vector<int>& perm = canon_perm_[sym];
          const double sign = ((sym & 1) ? -1.0 : 1.0) * ((sym & 2) ? -1.0 : 1.0) *
                              ((sym & 4) ? -1.0 : 1.0);
          for (int b = 0; b < nb; ++b)
            for (int a = 0; a < nb; ++a) {
              const int src = e * nb2 + perm[a + nb * b];
              for (int c = 0; c < 3; ++c) sc.P(a, c * nb + b) = x(c, src);
              if (uses_density(M))
                for (int c = 0; c < 3; ++c) sc.P(a, (3 + c) * nb + b) = (*dens)(c, src);
            }
          const int np = static_cast<int>(r.s.size());
          special_sum<M>(nb, sc.P, K, r.ls, r.dls, r.lt, r.dlt, r.w.data(), np, sign, x0, u0, sc,
                         acc);
          own_pairs += np;
        }
      } else {
        x0 = point_targets->col(k);
      }
      for (int e = 0; e < ne; ++e) {
        if (own[e]) continue;
        bool near = false;
        double s = 0, t = 0, h = 0, c = 1;
        const double crit = opt_.near_factor * esize[e];
        if ((x0 - centre[e]).norm() - radius[e] < crit) {
          nearest_point(mesh, x, e, x0, s, t, h, c);
          near = h < crit;
        }
        if (near) {
          ++near_elements;
          double hc = h / c;
          if (hc < 1e-12) hc = 0.0;
          polar_rule(s, t, hc, gen, grn, sc.s, sc.t, sc.w);
          const int np = static_cast<int>(sc.s.size());
          fill_bases(mesh, sc.s.data(), sc.t.data(), np, sc.ls, sc.dls, sc.lt, sc.dlt);
          for (int b = 0; b < nb; ++b)
            for (int a = 0; a < nb; ++a) {
              const int src = e * nb2 + a + nb * b;
              for (int cc = 0; cc < 3; ++cc) sc.P(a, cc * nb + b) = x(cc, src);
              if (uses_density(M))
                for (int cc = 0; cc < 3; ++cc) sc.P(a, (3 + cc) * nb + b) = (*dens)(cc, src);
            }
          special_sum<M>(nb, sc.P, K, sc.ls, sc.dls, sc.lt, sc.dlt, sc.w.data(), np, 1.0, x0,
                         u0, sc, acc);
          near_pairs += np;
        } else {
          const int q0 = e * nqe, q1 = q0 + nqe;
          for (int q = q0; q < q1; ++q) {
            const double dd[3] = {F(3, q), F(4, q), F(5, q)};
            const double nw[3] = {F(6, q), F(7, q), F(8, q)};
            kernel<M>(x0, u0, Fx[q], Fy[q], Fz[q], dd, nw, F(9, q), acc);
          }
          far_pairs += nqe;
        }
      }
      for (int r = 0; r < acc_rows; ++r) out(r, k) = acc[r];
    }
  }
  stats_.targets = ntar;
  stats_.far_pairs = far_pairs;
  stats_.own_pairs = own_pairs;
  stats_.near_pairs = near_pairs;
  stats_.near_elements = near_elements;
}

namespace {
std::vector<int> class_representatives(const geometry::Mesh& mesh) {
  std::vector<int> reps;
  reps.reserve(mesh.num_unique());
  for (const auto& c : mesh.classes()) reps.push_back(c.front());
  return reps;
}
Matrix3Xd scatter_classes(const geometry::Mesh& mesh, const MatrixXd& v) {
  Matrix3Xd out(3, mesh.num_local());
  const auto& cls = mesh.classes();
  for (size_t c = 0; c < cls.size(); ++c)
    for (int m : cls[c]) out.col(m) = v.col(static_cast<int>(c));
  return out;
}
}  // namespace

Matrix3Xd BoundaryOperators::single_layer(const Matrix3Xd& x, const Matrix3Xd& f) const {
  const std::vector<int> reps = class_representatives(mesh_);
  MatrixXd v;
  apply<Mode::Single>(x, &f, &reps, nullptr, v);
  return scatter_classes(mesh_, v);
}

void BoundaryOperators::single_layer(const Matrix3Xd& x, const Matrix3Xd& f,
                                     const std::vector<int>& targets, Matrix3Xd& out) const {
  MatrixXd v;
  apply<Mode::Single>(x, &f, &targets, nullptr, v);
  out = v;
}

Matrix3Xd BoundaryOperators::single_layer_at(const Matrix3Xd& x, const Matrix3Xd& f,
                                             const Matrix3Xd& points) const {
  MatrixXd v;
  apply<Mode::Single>(x, &f, nullptr, &points, v);
  return v;
}

Matrix3Xd BoundaryOperators::double_layer(const Matrix3Xd& x, const Matrix3Xd& u) const {
  const std::vector<int> reps = class_representatives(mesh_);
  MatrixXd v;
  apply<Mode::Double>(x, &u, &reps, nullptr, v);
  return scatter_classes(mesh_, v);
}

void BoundaryOperators::double_layer(const Matrix3Xd& x, const Matrix3Xd& u,
                                     const std::vector<int>& targets, Matrix3Xd& out) const {
  MatrixXd v;
  apply<Mode::Double>(x, &u, &targets, nullptr, v);
  out = v;
}

Matrix3Xd BoundaryOperators::single_layer_normal(const Matrix3Xd& x,
                                                 const std::vector<int>& targets) const {
  MatrixXd v;
  apply<Mode::SingleNormal>(x, nullptr, &targets, nullptr, v);
  return v;
}

MatrixXd BoundaryOperators::double_layer_normal(const Matrix3Xd& x,
                                                const std::vector<int>& targets) const {
  MatrixXd v;
  apply<Mode::DoubleNormal>(x, nullptr, &targets, nullptr, v);
  return v;
}

Matrix3Xd BoundaryOperators::single_layer_gauss(const geometry::Mesh& mesh, const Matrix3Xd& x,
                                                const Matrix3Xd& f, const Matrix3Xd& points,
                                                int nq) {
  const geometry::QuadratureSurface qs = geometry::sample_gauss(mesh, x, nq);
  const MatrixXd fq = geometry::to_gauss(mesh, f, qs.interp);
  Matrix3Xd out(3, points.cols());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < points.cols(); ++k) {
    Vector3d acc = Vector3d::Zero();
    const Vector3d x0 = points.col(k);
    for (int q = 0; q < qs.x.cols(); ++q) {
      const Vector3d r = qs.x.col(q) - x0;
      const double ir = 1.0 / r.norm();
      const Vector3d fv = fq.col(q);
      acc += qs.w[q] * (ir * fv + (ir * ir * ir * r.dot(fv)) * r);
    }
    out.col(k) = acc;
  }
  return out;
}

}  // namespace capflow::stokes
