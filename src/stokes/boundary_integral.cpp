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
constexpr int kMaxEdge = 256;  // Gauss points along an edge

using LineRule = BoundaryOperators::Rule;

// Perpendicular/sinh polar rule around p0 = (s0, t0) in [-1,1]^2 (see the header), built as
// lines: along every ray p0 -> edge point the coordinate perpendicular to that edge depends
// only on the ray fraction u, so for a fixed u the points of the two triangles on one edge
// form a line of constant s (edges s = +-1) or constant t (edges t = +-1).
// hu[edge] <= 0: plain Gauss in u (own element); hu > 0: radial sinh map u = hu sinh(sigma)
// (near elements), sigma in [0, asinh(1/hu)] split into panels of length <= 6.
// Edges in the order s = -1, s = +1 (constant-s lines), t = -1, t = +1 (constant-t lines).
void polar_rule(double s0, double t0, const double* hu, const spectral::Rule& ge,
                const spectral::Rule& gr, LineRule& R) {
  R.c.clear();
  R.start.clear();
  R.o.clear();
  R.w.clear();
  R.n0 = -1;
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
  const int nge = static_cast<int>(ge.x.size()), ngr = static_cast<int>(gr.x.size());
  for (int ei = 0; ei < 4; ++ei) {
    if (ei == 2) R.n0 = static_cast<int>(R.c.size());
    const Edge& E = edges[ei];
    if (E.d < kTiny) continue;
    const double h = hu[ei];
    const double sig_max = h > 0.0 ? std::asinh(1.0 / h) : 0.0;
    const int panels = h > 0.0 ? std::max(1, static_cast<int>(std::ceil(sig_max / kPanel))) : 1;
    const double dsig = sig_max / panels;
    // coordinate along the edge of the foot and of p0 (the same), and across
    const double p_along = E.axis == 1 ? t0 : s0;
    const double p_across = E.axis == 1 ? s0 : t0;
    const double f_across = E.axis == 1 ? E.fs : E.ft;
    // edge points (along-edge offset from the foot, times the Jacobian weight), per side
    double off[2][kMaxEdge], wedge[2][kMaxEdge];
    int cnt[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      const double L = k == 0 ? E.lo : E.hi;
      if (L < kTiny) continue;
      const double tau_max = std::asinh(L / E.d);
      const double dir = k == 0 ? -1.0 : 1.0;
      for (int a = 0; a < nge; ++a) {
        const double tau = 0.5 * tau_max * (ge.x[a] + 1.0);
        const double wt = 0.5 * tau_max * ge.w[a];
        off[k][a] = dir * E.d * std::sinh(tau);
        wedge[k][a] = wt * E.d * std::cosh(tau) * E.d;
      }
      cnt[k] = nge;
    }
    for (int pan = 0; pan < panels; ++pan)
      for (int b = 0; b < ngr; ++b) {
        double u, wu;
        if (h <= 0.0) {
          u = 0.5 * (gr.x[b] + 1.0);
          wu = 0.5 * gr.w[b];
        } else {
          const double sig = dsig * (pan + 0.5 * (gr.x[b] + 1.0));
          const double ex = std::exp(sig), sh = 0.5 * (ex - 1.0 / ex), ch = 0.5 * (ex + 1.0 / ex);
          u = h * (sig < 1e-3 ? std::sinh(sig) : sh);
          wu = 0.5 * dsig * gr.w[b] * h * ch;
        }
        R.c.push_back(p_across + u * (f_across - p_across));
        R.start.push_back(static_cast<int>(R.o.size()));
        for (int k = 0; k < 2; ++k)
          for (int a = 0; a < cnt[k]; ++a) {
            R.o.push_back(p_along + u * off[k][a]);
            R.w.push_back(wedge[k][a] * u * wu);
          }
      }
  }
  R.start.push_back(static_cast<int>(R.o.size()));
}

// Lagrange basis l_j(t) and l_j'(t) through the Gauss-Lobatto nodes (barycentric form).
// Far from the nodes the derivative uses l_j' = l_j (sum_k l_k/(t - x_k) - 1/(t - x_j))
// (relative error ~ eps / min |t - x_k|); within 1e-2 of a node it uses l' = D^T l (D the
// differentiation matrix, exact for the degree nb-2 derivative).
void basis(const geometry::Mesh& mesh, double t, double* l, double* dl) {
  const int n = mesh.nb();
  const double* x = mesh.nodes().data();
  const double* bw = mesh.bary().data();
  double inv[kMaxNb];
  double nearest = 2.0;
  for (int j = 0; j < n; ++j) nearest = std::min(nearest, std::abs(t - x[j]));
  if (nearest == 0.0) {
    spectral::lagrange_basis(mesh.nodes(), mesh.bary(), t, l, dl);
    return;
  }
  double S = 0.0;
  for (int j = 0; j < n; ++j) {
    inv[j] = 1.0 / (t - x[j]);
    l[j] = bw[j] * inv[j];
    S += l[j];
  }
  const double iS = 1.0 / S;
  double T = 0.0;
  for (int j = 0; j < n; ++j) {
    l[j] *= iS;
    T += l[j] * inv[j];
  }
  if (nearest >= 1e-2) {
    for (int j = 0; j < n; ++j) dl[j] = l[j] * (T - inv[j]);
  } else {
    const MatrixXd& D = mesh.diff();  // D(m, k) = l_k'(x_m)
    for (int k = 0; k < n; ++k) {
      const double* col = D.col(k).data();
      double v = 0.0;
      for (int m = 0; m < n; ++m) v += l[m] * col[m];
      dl[k] = v;
    }
  }
}

// Bases of a line rule (Lc, dLc at the line coordinates; LoT, dLoT at the points). The
// matrices are resized only when they are too small (scratch reuse).
void fill_bases(const geometry::Mesh& mesh, LineRule& R) {
  const int nb = mesh.nb(), nl = R.nl(), np = R.np();
  if (R.Lc.cols() < nl) {
    R.Lc.resize(nb, nl);
    R.dLc.resize(nb, nl);
  }
  for (int l = 0; l < nl; ++l) basis(mesh, R.c[l], R.Lc.col(l).data(), R.dLc.col(l).data());
  if (R.LoT.rows() < np) {  // leading dimension = rows (may exceed np)
    R.LoT.resize(np, nb);
    R.dLoT.resize(np, nb);
  }
  const long ld = R.LoT.rows();
  double l[kMaxNb], dl[kMaxNb];
  double* L = R.LoT.data();
  double* dL = R.dLoT.data();
  for (int p = 0; p < np; ++p) {
    basis(mesh, R.o[p], l, dl);
    for (int j = 0; j < nb; ++j) {
      L[p + ld * j] = l[j];
      dL[p + ld * j] = dl[j];
    }
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
                   double& s, double& t, double& h, Vector3d& xs, Vector3d& xt) {
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
  xs = p.xs;
  xt = p.xt;
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
  MatrixXd D0, D1;  // element data, nb x (K nb): D0(i, k nb + j) = D1(j, k nb + i) = X_k(i, j)
  RowMat A, B;      // stage 1: values / derivative across, per line
  std::vector<double> v;  // stage 2 per line: 12 arrays of the line's length
  LineRule near;
};

// Element data (x and, if K == 6, the density) in the orientation given by perm (canonical
// (a + nb b) -> local node within the element).
void load_element(int nb, int K, const Matrix3Xd& x, const Matrix3Xd* dens, int base,
                  const int* perm, Scratch& sc) {
  for (int b = 0; b < nb; ++b)
    for (int a = 0; a < nb; ++a) {
      const int src = base + (perm ? perm[a + nb * b] : a + nb * b);
      for (int c = 0; c < 3; ++c) {
        sc.D0(a, c * nb + b) = x(c, src);
        sc.D1(b, c * nb + a) = x(c, src);
      }
      if (K == 6)
        for (int c = 0; c < 3; ++c) {
          sc.D0(a, (3 + c) * nb + b) = (*dens)(c, src);
          sc.D1(b, (3 + c) * nb + a) = (*dens)(c, src);
        }
    }
}

// Sum the kernel over the points of one line rule; the element data are in sc.D0/D1 (in the
// rule's orientation); sign: orientation of the rule's (s, t) relative to the element's.
// Stage 1: for every line, the 1-D interpolation across the lines (dense products
// Lc^T D: lines x (K nb)); stage 2: per point, length-nb dot products along the line.
template <BoundaryOperators::Mode M>
void line_sum(int nb, int K, const LineRule& R, double sign, const Vector3d& x0,
              const Vector3d& u0, Scratch& sc, double* acc) {
  using Mode = BoundaryOperators::Mode;
  const int nl = R.nl(), n0 = R.n0, n1 = nl - n0;
  const int Kn = K * nb, n3 = 3 * nb;
  if (n0 > 0) {
    sc.A.topLeftCorner(n0, Kn).noalias() = R.Lc.leftCols(n0).transpose() * sc.D0.leftCols(Kn);
    sc.B.topLeftCorner(n0, n3).noalias() = R.dLc.leftCols(n0).transpose() * sc.D0.leftCols(n3);
  }
  if (n1 > 0) {
    sc.A.block(n0, 0, n1, Kn).noalias() =
        R.Lc.middleCols(n0, n1).transpose() * sc.D1.leftCols(Kn);
    sc.B.block(n0, 0, n1, n3).noalias() =
        R.dLc.middleCols(n0, n1).transpose() * sc.D1.leftCols(n3);
  }
  const int ld = static_cast<int>(R.LoT.rows());
  for (int l = 0; l < nl; ++l) {
    const int p0 = R.start[l], m = R.start[l + 1] - p0;
    if (m == 0) continue;
    const double* A = sc.A.row(l).data();
    const double* B = sc.B.row(l).data();
    // 12 arrays of length m (stride ms): x(3), f(3), d/d(across)(3), d/d(along)(3)
    const int ms = (m + 3) & ~3;
    double* __restrict X0 = sc.v.data();
    double* __restrict X1 = X0 + ms;
    double* __restrict X2 = X0 + 2 * ms;
    double* __restrict F0 = X0 + 3 * ms;
    double* __restrict F1 = X0 + 4 * ms;
    double* __restrict F2 = X0 + 5 * ms;
    double* __restrict A0 = X0 + 6 * ms;
    double* __restrict A1 = X0 + 7 * ms;
    double* __restrict A2 = X0 + 8 * ms;
    double* __restrict O0 = X0 + 9 * ms;
    double* __restrict O1 = X0 + 10 * ms;
    double* __restrict O2 = X0 + 11 * ms;
    for (int p = 0; p < 12 * ms; ++p) X0[p] = 0.0;
    for (int j = 0; j < nb; ++j) {
      const double* __restrict lo = R.LoT.data() + static_cast<long>(j) * ld + p0;
      const double* __restrict dlo = R.dLoT.data() + static_cast<long>(j) * ld + p0;
      const double c0 = A[j], c1 = A[nb + j], c2 = A[2 * nb + j];
      const double d0 = B[j], d1 = B[nb + j], d2 = B[2 * nb + j];
#pragma omp simd
      for (int p = 0; p < m; ++p) {
        X0[p] += c0 * lo[p];
        X1[p] += c1 * lo[p];
        X2[p] += c2 * lo[p];
        A0[p] += d0 * lo[p];
        A1[p] += d1 * lo[p];
        A2[p] += d2 * lo[p];
        O0[p] += c0 * dlo[p];
        O1[p] += c1 * dlo[p];
        O2[p] += c2 * dlo[p];
      }
      if (K == 6) {
        const double e0 = A[3 * nb + j], e1 = A[4 * nb + j], e2 = A[5 * nb + j];
#pragma omp simd
        for (int p = 0; p < m; ++p) {
          F0[p] += e0 * lo[p];
          F1[p] += e1 * lo[p];
          F2[p] += e2 * lo[p];
        }
      }
    }
    // n = x_s x x_t: constant-s lines: x_s = Da, x_t = Do; constant-t lines: swapped.
    const double sg = l < n0 ? sign : -sign;
    const double* w = R.w.data() + p0;
    double s0 = 0, s1 = 0, s2 = 0;
    double s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0, s8 = 0;
#pragma omp simd reduction(+ : s0, s1, s2, s3, s4, s5, s6, s7, s8)
    for (int p = 0; p < m; ++p) {
      const double nx = sg * (A1[p] * O2[p] - A2[p] * O1[p]);
      const double ny = sg * (A2[p] * O0[p] - A0[p] * O2[p]);
      const double nz = sg * (A0[p] * O1[p] - A1[p] * O0[p]);
      const double rx = X0[p] - x0[0], ry = X1[p] - x0[1], rz = X2[p] - x0[2];
      const double r2 = rx * rx + ry * ry + rz * rz;
      const double ir = 1.0 / std::sqrt(r2);
      const double ir3 = ir * ir * ir;
      if constexpr (M == Mode::Single) {
        const double fx = F0[p], fy = F1[p], fz = F2[p];
        const double wj = w[p] * std::sqrt(nx * nx + ny * ny + nz * nz);
        const double rd = rx * fx + ry * fy + rz * fz;
        const double a = wj * ir, bb = wj * rd * ir3;
        s0 += a * fx + bb * rx;
        s1 += a * fy + bb * ry;
        s2 += a * fz + bb * rz;
      } else if constexpr (M == Mode::SingleNormal) {
        const double rn = (rx * nx + ry * ny + rz * nz) * w[p];
        const double bb = rn * ir3, a = ir * w[p];
        s0 += a * nx + bb * rx;
        s1 += a * ny + bb * ry;
        s2 += a * nz + bb * rz;
      } else if constexpr (M == Mode::Double) {
        const double qx = F0[p] - u0[0], qy = F1[p] - u0[1], qz = F2[p] - u0[2];
        const double rq = rx * qx + ry * qy + rz * qz;
        const double rn = rx * nx + ry * ny + rz * nz;
        const double a = -6.0 * w[p] * rq * rn * ir3 * ir * ir;
        s0 += a * rx;
        s1 += a * ry;
        s2 += a * rz;
      } else {
        const double rn = rx * nx + ry * ny + rz * nz;
        const double a = -6.0 * w[p] * rn * ir3 * ir * ir;
        s0 += a * rx * rx;
        s1 += a * ry * rx;
        s2 += a * rz * rx;
        s3 += a * rx * ry;
        s4 += a * ry * ry;
        s5 += a * rz * ry;
        s6 += a * rx * rz;
        s7 += a * ry * rz;
        s8 += a * rz * rz;
      }
    }
    acc[0] += s0;
    acc[1] += s1;
    acc[2] += s2;
    if constexpr (M == Mode::DoubleNormal) {
      acc[3] += s3;
      acc[4] += s4;
      acc[5] += s5;
      acc[6] += s6;
      acc[7] += s7;
      acc[8] += s8;
    }
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
  if (opt_.n_edge > kMaxEdge || opt_.n_edge_near > kMaxEdge)
    throw std::invalid_argument("BoundaryOperators: n_edge / n_edge_near > 256");
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
        const double hu[4] = {0, 0, 0, 0};
        polar_rule(xi[ic], xi[jc], hu, ge, gr, r);
        fill_bases(mesh, r);
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
  for (const Rule& r : rules_) n += r.np();
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
  // near rule: 4 edges x n_radial_near x panels (asinh(1/hu) <= asinh(1e14) < 6 * 6) lines
  const int max_near_lines = 4 * opt_.n_radial_near * 6;
  int max_lines = max_near_lines, max_line = 2 * opt_.n_edge_near;
  for (const Rule& r : rules_) {
    max_lines = std::max(max_lines, r.nl());
    for (int l = 0; l < r.nl(); ++l) max_line = std::max(max_line, r.start[l + 1] - r.start[l]);
  }

  long far_pairs = 0, own_pairs = 0, near_pairs = 0, near_elements = 0;
#pragma omp parallel reduction(+ : far_pairs, own_pairs, near_pairs, near_elements)
  {
    Scratch sc;
    sc.D0.resize(nb, 6 * nb);
    sc.D1.resize(nb, 6 * nb);
    sc.A.resize(max_lines, 6 * nb);
    sc.B.resize(max_lines, 3 * nb);
    sc.v.resize(12 * static_cast<size_t>(max_line));
    sc.near.Lc.resize(nb, max_near_lines);
    sc.near.dLc.resize(nb, max_near_lines);
    std::vector<char> own(ne);
    const double* Fx = F.row(0).data();
    const double* Fy = F.row(1).data();
    const double* Fz = F.row(2).data();

#pragma omp for schedule(dynamic, 1)
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
          const double sign = ((sym & 1) ? -1.0 : 1.0) * ((sym & 2) ? -1.0 : 1.0) *
                              ((sym & 4) ? -1.0 : 1.0);
          load_element(nb, K, x, dens, e * nb2, canon_perm_[sym].data(), sc);
          line_sum<M>(nb, K, r, sign, x0, u0, sc, acc);
          own_pairs += r.np();
        }
      } else {
        x0 = point_targets->col(k);
      }
      for (int e = 0; e < ne; ++e) {
        if (own[e]) continue;
        bool near = false;
        double s = 0, t = 0, h = 0;
        Vector3d xs, xt;
        const double crit = opt_.near_factor * esize[e];
        if ((x0 - centre[e]).norm() - radius[e] < crit) {
          nearest_point(mesh, x, e, x0, s, t, h, xs, xt);
          near = h < crit;
        }
        if (near) {
          ++near_elements;
          // radial sinh scale per edge: h / max |J v| over the rays to the edge's two ends
          // (|J v|^2 is convex along the edge), J = [x_s x_t] at p*.
          double hu[4];
          const double ends[4][2][2] = {{{-1, -1}, {-1, 1}},
                                        {{1, -1}, {1, 1}},
                                        {{-1, -1}, {1, -1}},
                                        {{-1, 1}, {1, 1}}};
          for (int ei = 0; ei < 4; ++ei) {
            double jv = 0;
            for (int k2 = 0; k2 < 2; ++k2)
              jv = std::max(jv, (xs * (ends[ei][k2][0] - s) + xt * (ends[ei][k2][1] - t)).norm());
            hu[ei] = h / jv;
            if (hu[ei] < 1e-13) hu[ei] = 0.0;
          }
          polar_rule(s, t, hu, gen, grn, sc.near);
          fill_bases(mesh, sc.near);
          load_element(nb, K, x, dens, e * nb2, nullptr, sc);
          line_sum<M>(nb, K, sc.near, 1.0, x0, u0, sc, acc);
          near_pairs += sc.near.np();
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
