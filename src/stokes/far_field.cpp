#include "stokes/far_field.h"

#include <algorithm>
#include <cmath>

#include "spectral/spectral.h"
#include "spectral/target_clones.h"
#include "stokes/kernel_point.h"
#include "stokes/thread_buffers.h"

namespace capflow::stokes {

using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

FarBasis far_basis(const VectorXd& nodes, int nq) {
  const spectral::Rule gq = spectral::gauss_legendre(nq);
  return {gq.w, spectral::interpolation_matrix(nodes, gq.x),
          spectral::derivative_matrix(nodes, gq.x)};
}

namespace {
// Component k of v at the nodes of element e as an nb x nb grid: X(i, j) at node (i, j), i along
// xi (local node e nb^2 + j nb + i).
void node_grid(const Matrix3Xd& v, int nb, int e, int k, MatrixXd& X) {
  X.resize(nb, nb);
  const int base = e * nb * nb;
  for (int j = 0; j < nb; ++j)
    for (int i = 0; i < nb; ++i) X(i, j) = v(k, base + j * nb + i);
}
}  // namespace

template <Mode M>
void far_geometry(const geometry::Mesh& mesh, const Matrix3Xd& x, const FarBasis& fb, int e,
                  FarData& F, double* esize) {
  const int nb = mesh.nb(), nq = static_cast<int>(fb.w.size());
  const MatrixXd &I = fb.I, &Id = fb.Id;
  // the thread's workspace for this order, kept across calls (stokes/thread_buffers.h):
  // allocated per call, these temporaries made the malloc arena grow and trim (~50 page faults a
  // call at NE=6 NB=10)
  FarWorkspace& ws = far_workspace(thread_buffers<M>(), nq);
  MatrixXd &X = ws.X, &XI = ws.XI, &IX = ws.IX;
  MatrixXd *xsq = ws.xsq, *xtq = ws.xtq;
  // The points in the order of F.d's columns (q = a + nq b: an nq x nq column-major matrix per
  // row, so the products below write the positions, and far_density the density, straight into
  // F.d)
  const int q0 = e * nq * nq;
  double* __restrict out[10];
  for (int r = 0; r < 10; ++r) out[r] = F.d.row(r).data() + q0;
  for (int k = 0; k < 3; ++k) {
    node_grid(x, nb, e, k, X);
    XI.noalias() = X * I.transpose();
    Eigen::Map<MatrixXd>(out[k], nq, nq).noalias() = I * XI;
    xsq[k].noalias() = Id * XI;
    IX.noalias() = I * X;
    xtq[k].noalias() = IX * Id.transpose();
  }
  // one vectorised loop per column b of the Gauss grid; the single layer reads only w J
  const double* gw = fb.w.data();
  constexpr bool normals = M != Mode::Single;
  double ls = 0, lt = 0;
  for (int b = 0; b < nq; ++b) {
    const int o = b * nq;
    const double* __restrict sx = xsq[0].data() + o;
    const double* __restrict sy = xsq[1].data() + o;
    const double* __restrict sz = xsq[2].data() + o;
    const double* __restrict tx = xtq[0].data() + o;
    const double* __restrict ty = xtq[1].data() + o;
    const double* __restrict tz = xtq[2].data() + o;
    const double wb = gw[b];
#pragma omp simd reduction(+ : ls, lt)
    for (int a = 0; a < nq; ++a) {
      const double w = gw[a] * wb;
      const double cx = sy[a] * tz[a] - sz[a] * ty[a];
      const double cy = sz[a] * tx[a] - sx[a] * tz[a];
      const double cz = sx[a] * ty[a] - sy[a] * tx[a];
      ls += w * std::sqrt(sx[a] * sx[a] + sy[a] * sy[a] + sz[a] * sz[a]);
      lt += w * std::sqrt(tx[a] * tx[a] + ty[a] * ty[a] + tz[a] * tz[a]);
      if constexpr (normals) {
        out[6][o + a] = w * cx;
        out[7][o + a] = w * cy;
        out[8][o + a] = w * cz;
      }
      out[9][o + a] = w * std::sqrt(cx * cx + cy * cy + cz * cz);
    }
  }
  // mean length of the longer family of coordinate lines (= 2 * mean |x_xi| or |x_eta|)
  if (esize) *esize = 0.5 * std::max(ls, lt);
}

template <Mode M>
void far_density(const geometry::Mesh& mesh, const Matrix3Xd* dens, const FarBasis& fb, int e,
                 FarData& F) {
  const int nb = mesh.nb(), nq = static_cast<int>(fb.w.size()), nqe = nq * nq;
  if constexpr (!uses_density(M)) {
    for (int k = 0; k < 3; ++k) std::fill_n(F.d.row(3 + k).data() + e * nqe, nqe, 0.0);
  } else {
    FarWorkspace& ws = far_workspace(thread_buffers<M>(), nq);
    for (int k = 0; k < 3; ++k) {
      node_grid(*dens, nb, e, k, ws.X);
      ws.IX.noalias() = fb.I * ws.X;
      Eigen::Map<MatrixXd>(F.d.row(3 + k).data() + e * nqe, nq, nq).noalias() =
          ws.IX * fb.I.transpose();
    }
  }
}

template <Mode M>
void far_data(const geometry::Mesh& mesh, const Matrix3Xd& x, const Matrix3Xd* dens,
              const FarBasis& fb, int e, FarData& F, double* esize) {
  far_geometry<M>(mesh, x, fb, e, F, esize);
  far_density<M>(mesh, dens, fb, e, F);
}

namespace {

// Single-layer kernel sum over far points [q0, q1) (rows of F.d); cloned like single_line.
CAPFLOW_TARGET_CLONES("arch=x86-64-v4", "arch=x86-64-v3", "default")
void far_single(const double* px, const double* py, const double* pz, const double* fx,
                const double* fy, const double* fz, const double* wj, int q0, int q1,
                const double* x0, double* acc) {
  const double X0 = x0[0], X1 = x0[1], X2 = x0[2];
  double s0 = 0, s1 = 0, s2 = 0;
#pragma omp simd reduction(+ : s0, s1, s2)
  for (int q = q0; q < q1; ++q) {
    const double rx = px[q] - X0, ry = py[q] - X1, rz = pz[q] - X2;
    const double ir = 1.0 / std::sqrt(rx * rx + ry * ry + rz * rz);
    const double rd = rx * fx[q] + ry * fy[q] + rz * fz[q];
    const double a = wj[q] * ir, b = a * ir * ir * rd;
    s0 += a * fx[q] + b * rx;
    s1 += a * fy[q] + b * ry;
    s2 += a * fz[q] + b * rz;
  }
  acc[0] += s0;
  acc[1] += s1;
  acc[2] += s2;
}

}  // namespace

// Kernel sum over the far points [q0, q1) of F.
template <Mode M>
void far_sum(const FarData& F, int q0, int q1, const Vector3d& x0, const Vector3d& u0,
             double* acc) {
  if constexpr (M == Mode::Single) {
    far_single(F.d.row(0).data(), F.d.row(1).data(), F.d.row(2).data(), F.d.row(3).data(),
               F.d.row(4).data(), F.d.row(5).data(), F.d.row(9).data(), q0, q1, x0.data(), acc);
  } else {
    const double* __restrict px = F.d.row(0).data();
    const double* __restrict py = F.d.row(1).data();
    const double* __restrict pz = F.d.row(2).data();
    const double* __restrict fx = F.d.row(3).data();
    const double* __restrict fy = F.d.row(4).data();
    const double* __restrict fz = F.d.row(5).data();
    const double* __restrict nx = F.d.row(6).data();
    const double* __restrict ny = F.d.row(7).data();
    const double* __restrict nz = F.d.row(8).data();
    const double X0 = x0[0], X1 = x0[1], X2 = x0[2];
    const double U0 = u0[0], U1 = u0[1], U2 = u0[2];
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0, s8 = 0;
#pragma omp simd reduction(+ : s0, s1, s2, s3, s4, s5, s6, s7, s8)
    for (int q = q0; q < q1; ++q)
      kernel_point<M>(px[q] - X0, py[q] - X1, pz[q] - X2, nx[q], ny[q], nz[q], fx[q] - U0,
                      fy[q] - U1, fz[q] - U2, s0, s1, s2, s3, s4, s5, s6, s7, s8);
    add_sums<M>(acc, s0, s1, s2, s3, s4, s5, s6, s7, s8);
  }
}

template void far_geometry<Mode::Single>(const geometry::Mesh&, const Matrix3Xd&, const FarBasis&,
                                         int, FarData&, double*);
template void far_density<Mode::Single>(const geometry::Mesh&, const Matrix3Xd*, const FarBasis&,
                                        int, FarData&);
template void far_data<Mode::Single>(const geometry::Mesh&, const Matrix3Xd&, const Matrix3Xd*,
                                     const FarBasis&, int, FarData&, double*);
template void far_sum<Mode::Single>(const FarData&, int, int, const Vector3d&, const Vector3d&,
                                    double*);
template void far_geometry<Mode::SingleNormal>(const geometry::Mesh&, const Matrix3Xd&,
                                               const FarBasis&, int, FarData&, double*);
template void far_density<Mode::SingleNormal>(const geometry::Mesh&, const Matrix3Xd*,
                                              const FarBasis&, int, FarData&);
template void far_data<Mode::SingleNormal>(const geometry::Mesh&, const Matrix3Xd&,
                                           const Matrix3Xd*, const FarBasis&, int, FarData&,
                                           double*);
template void far_sum<Mode::SingleNormal>(const FarData&, int, int, const Vector3d&,
                                          const Vector3d&, double*);
template void far_geometry<Mode::Double>(const geometry::Mesh&, const Matrix3Xd&, const FarBasis&,
                                         int, FarData&, double*);
template void far_density<Mode::Double>(const geometry::Mesh&, const Matrix3Xd*, const FarBasis&,
                                        int, FarData&);
template void far_data<Mode::Double>(const geometry::Mesh&, const Matrix3Xd&, const Matrix3Xd*,
                                     const FarBasis&, int, FarData&, double*);
template void far_sum<Mode::Double>(const FarData&, int, int, const Vector3d&, const Vector3d&,
                                    double*);
template void far_geometry<Mode::DoubleNormal>(const geometry::Mesh&, const Matrix3Xd&,
                                               const FarBasis&, int, FarData&, double*);
template void far_density<Mode::DoubleNormal>(const geometry::Mesh&, const Matrix3Xd*,
                                              const FarBasis&, int, FarData&);
template void far_data<Mode::DoubleNormal>(const geometry::Mesh&, const Matrix3Xd&,
                                           const Matrix3Xd*, const FarBasis&, int, FarData&,
                                           double*);
template void far_sum<Mode::DoubleNormal>(const FarData&, int, int, const Vector3d&,
                                          const Vector3d&, double*);

template void far_geometry<Mode::DoubleMatrix>(const geometry::Mesh&, const Matrix3Xd&,
                                               const FarBasis&, int, FarData&, double*);
template void far_density<Mode::DoubleMatrix>(const geometry::Mesh&, const Matrix3Xd*,
                                              const FarBasis&, int, FarData&);
template void far_data<Mode::DoubleMatrix>(const geometry::Mesh&, const Matrix3Xd&,
                                           const Matrix3Xd*, const FarBasis&, int, FarData&,
                                           double*);

}  // namespace capflow::stokes
