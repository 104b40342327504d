// Unit tests of the Stokes boundary-integral operators: identities on the unit sphere.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <cstdio>
#include <thread>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"
#include "stokes/boundary_integral.h"
#include "stokes/kernels.h"
#include "stokes/thread_cap.h"

using namespace capflow;
using Eigen::Matrix3d;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {
constexpr double kPi = 3.14159265358979323846;

// Node type of a local node: 0 interior, 1 next to an edge, 2 on an edge, 3 corner.
int node_type(const geometry::Mesh& m, int loc) {
  const int nb = m.nb();
  const int i = loc % nb, j = (loc / nb) % nb;
  auto on = [nb](int k) { return k == 0 || k == nb - 1; };
  auto next = [nb](int k) { return k == 1 || k == nb - 2; };
  if (on(i) && on(j)) return 3;
  if (on(i) || on(j)) return 2;
  if (next(i) || next(j)) return 1;
  return 0;
}

std::vector<int> all_reps(const geometry::Mesh& m) {
  std::vector<int> r;
  for (const auto& c : m.classes()) r.push_back(c.front());
  return r;
}

struct SphereErrors {
  double sn[4] = {0, 0, 0, 0}, tn[4] = {0, 0, 0, 0}, s[4] = {0, 0, 0, 0}, tr[4] = {0, 0, 0, 0};
};

// Targets: every local node of elements 0 and ne-1 (all four node types, corners shared by
// 3 or 4 elements).
std::vector<int> two_elements(const geometry::Mesh& m) {
  std::vector<int> r;
  const int n2 = m.nb() * m.nb();
  for (int e : {0, m.ne() - 1})
    for (int k = 0; k < n2; ++k) r.push_back(e * n2 + k);
  return r;
}

// Largest angle between the normals that coincident copies of a node carry (the interpolated
// surface has a kink of this size along element edges).
double max_normal_jump(const geometry::Mesh& m, const Matrix3Xd& x) {
  const geometry::SurfaceGeometry g = geometry::compute_geometry(m, x);
  double jump = 0;
  for (const auto& c : m.classes())
    for (int q : c) jump = std::max(jump, (g.n.col(q) - g.n.col(c.front())).norm());
  return jump;
}

SphereErrors sphere_errors(int ne, int nb, bool all) {
  geometry::Mesh mesh(ne, nb);
  stokes::BoundaryOperators op(mesh);
  const Matrix3Xd& x = mesh.reference();
  const std::vector<int> t = all ? all_reps(mesh) : two_elements(mesh);
  const Matrix3Xd sn = op.single_layer_normal(x, t);
  const MatrixXd tn = op.double_layer_normal(x, t);
  Matrix3Xd sl[3];
  for (int j = 0; j < 3; ++j) {
    Matrix3Xd f = Matrix3Xd::Zero(3, mesh.num_local());
    f.row(j).setOnes();
    op.single_layer(x, f, t, sl[j]);
  }
  const Vector3d U(0.3, -0.7, 0.5);
  Matrix3Xd f = (-1.5 * U).replicate(1, mesh.num_local()), v;
  op.single_layer(x, f, t, v);
  SphereErrors e;
  for (size_t k = 0; k < t.size(); ++k) {
    const int ty = node_type(mesh, t[k]);
    e.sn[ty] = std::max(e.sn[ty], sn.col(k).cwiseAbs().maxCoeff());
    Matrix3d T = Eigen::Map<const Matrix3d>(tn.col(k).data());
    e.tn[ty] = std::max(e.tn[ty], (T + 4 * kPi * Matrix3d::Identity()).cwiseAbs().maxCoeff());
    for (int j = 0; j < 3; ++j) {
      Vector3d ex = Vector3d::Zero();
      ex[j] = 16 * kPi / 3;
      e.s[ty] = std::max(e.s[ty], (sl[j].col(k) - ex).cwiseAbs().maxCoeff());
    }
    const Vector3d u = -v.col(k) / (8 * kPi);
    e.tr[ty] = std::max(e.tr[ty], (u - U).cwiseAbs().maxCoeff());
  }
  std::printf(
      "NE=%d NB=%d (%zu targets, normal jump at edges %.1e)  type: interior / next-to-edge / edge "
      "/ corner\n",
      ne, nb, t.size(), max_normal_jump(mesh, x));
  std::printf("  |INT S.n|          %.2e %.2e %.2e %.2e\n", e.sn[0], e.sn[1], e.sn[2], e.sn[3]);
  std::printf("  |INT T.n + 4pi I|  %.2e %.2e %.2e %.2e\n", e.tn[0], e.tn[1], e.tn[2], e.tn[3]);
  std::printf("  |INT S - 16pi/3 I| %.2e %.2e %.2e %.2e\n", e.s[0], e.s[1], e.s[2], e.s[3]);
  std::printf("  |u - U| transl.   %.2e %.2e %.2e %.2e\n", e.tr[0], e.tr[1], e.tr[2], e.tr[3]);
  return e;
}

double maxof(const double* a) {
  return std::max(std::max(a[0], a[1]), std::max(a[2], a[3]));
}

}  // namespace

TEST(StokesKernels, ClosedForms) {
  const Vector3d x0(0.1, -0.2, 0.3), x(0.7, 0.4, -0.5), f(1.0, -2.0, 0.5), n(0.2, 0.3, 0.9);
  const Matrix3d S = stokes::stokeslet(x0, x);
  EXPECT_LT((S - S.transpose()).norm(), 1e-15);
  EXPECT_LT((S * f - stokes::stokeslet_apply(x0, x, f)).norm(), 1e-14);
  // Stokeslet is divergence-free in x: sum_i d S_ij / d x_i = 0 (central differences).
  const double hh = 1e-5;
  for (int j = 0; j < 3; ++j) {
    double div = 0;
    for (int i = 0; i < 3; ++i) {
      Vector3d xp = x, xm = x;
      xp[i] += hh;
      xm[i] -= hh;
      div += (stokes::stokeslet(x0, xp)(i, j) - stokes::stokeslet(x0, xm)(i, j)) / (2 * hh);
    }
    EXPECT_LT(std::abs(div), 1e-8);
  }
  const Matrix3d Tn = stokes::stresslet_normal(x0, x, n);
  EXPECT_LT((Tn * f - stokes::stresslet_apply(x0, x, f, n)).norm(), 1e-14);
}

namespace {
// INT T.n dS = -4 pi I holds where the surface is smooth. On an element edge the interpolated
// surface has a kink (normal jump ~1e-6 at NB=12) and the integral is minus twice the solid
// angle there, so edge and corner nodes get a bound proportional to the jump.
// Interior and next-to-edge nodes: the 1e-8 target.
void check_sphere(int ne, int nb, double tol_exact, double tol_tn = 1e-8) {
  const SphereErrors e = sphere_errors(ne, nb, false);
  EXPECT_LT(maxof(e.sn), 1e-8 * 16 * kPi / 3) << "NE=" << ne;
  EXPECT_LT(std::max(e.tn[0], e.tn[1]), tol_tn) << "NE=" << ne;
  EXPECT_LT(std::max(e.tn[2], e.tn[3]), 1e-4) << "NE=" << ne;
  EXPECT_LT(maxof(e.s), tol_exact) << "NE=" << ne;
  EXPECT_LT(maxof(e.tr), tol_exact) << "NE=" << ne;
}
}  // namespace

TEST(StokesSphere, IdentitiesNE6NB12) {
  check_sphere(6, 12, 1e-6);
}
TEST(StokesSphere, IdentitiesNE10NB12) {
  check_sphere(10, 12, 1e-6);
}
TEST(StokesSphere, IdentitiesNE14NB12) {
  check_sphere(14, 12, 1e-6);
}
TEST(StokesSphere, IdentitiesNE6NB16) {
  check_sphere(6, 16, 1e-9);
}
TEST(StokesSphere, IdentitiesNE10NB16) {
  check_sphere(10, 16, 1e-9);
}
TEST(StokesSphere, IdentitiesNE14NB16) {
  check_sphere(14, 16, 1e-9);
}

// The subset API gives the same values as the all-nodes API; off-surface points agree with
// plain high-order Gauss; a point just inside the sphere still sees INT S dS = 16 pi/3 I.
TEST(StokesApi, SubsetPointsAndGauss) {
  geometry::Mesh mesh(6, 8);
  stokes::BoundaryOperators op(mesh);
  const Matrix3Xd x =
      geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.3, 0.8, 1.0));
  Matrix3Xd f(3, mesh.num_local());
  for (int m = 0; m < mesh.num_local(); ++m)
    f.col(m) = Vector3d(std::sin(x(0, m)), x(1, m) * x(2, m), std::exp(0.3 * x(0, m)));
  const Matrix3Xd all = op.single_layer(x, f);
  const std::vector<int> t = {0, 5, 17, 63, 200, 383};
  Matrix3Xd sub;
  op.single_layer(x, f, t, sub);
  for (size_t k = 0; k < t.size(); ++k) EXPECT_LT((sub.col(k) - all.col(t[k])).norm(), 1e-13);
  // far points
  Matrix3Xd p(3, 3);
  p << 3.0, 0.0, -2.5, 0.5, 2.0, 0.3, 0.2, -0.4, 2.2;
  const Matrix3Xd a = op.single_layer_at(x, f, p);
  const Matrix3Xd g = stokes::BoundaryOperators::single_layer_gauss(mesh, x, f, p, 30);
  std::printf("far points against 30-point Gauss: %.2e (far tier nq = %d)\n",
              (a - g).cwiseAbs().maxCoeff(), op.options().nq_far);
  EXPECT_LT((a - g).cwiseAbs().maxCoeff(), 1e-7);
  // unit sphere, points at radius 0.999 (near-singular from inside) and on node positions
  const Matrix3Xd& s = mesh.reference();
  Matrix3Xd q(3, 4);
  q.col(0) = 0.999 * s.col(9);
  q.col(1) = 0.999 * s.col(1);
  q.col(2) = 0.9999 * s.col(0);
  q.col(3) = s.col(10);
  for (int j = 0; j < 3; ++j) {
    Matrix3Xd fj = Matrix3Xd::Zero(3, mesh.num_local());
    fj.row(j).setOnes();
    const Matrix3Xd v = op.single_layer_at(s, fj, q);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(v(j, k), 16 * kPi / 3, 1e-4) << j << " " << k;
  }
}

// scale_orders multiplies the resolved orders per tier; with every order tripled, the on-surface
// point path (near rules with h = 0) agrees with the node path's own-element rules at the nodes:
// two different quadratures of the same weakly singular integral meeting at the reference level.
TEST(StokesApi, ScaledOrdersMakeThePointPathAReference) {
  geometry::Mesh mesh(6, 10);
  const stokes::BoundaryOperators op(mesh);
  const stokes::QuadratureOptions& r = op.options();
  const stokes::QuadratureOptions q = stokes::scale_orders(r, {2.0, 1.5, 3.0});
  EXPECT_EQ(q.nq_far, 2 * r.nq_far);
  EXPECT_EQ(q.nq_mid, 2 * r.nq_mid);
  EXPECT_EQ(q.single_nq_mid, 2 * r.single_nq_mid);
  EXPECT_EQ(q.n_edge, static_cast<int>(std::lround(1.5 * r.n_edge)));
  EXPECT_DOUBLE_EQ(q.own_edge_base, 1.5 * r.own_edge_base);  // every side's order x 1.5
  EXPECT_DOUBLE_EQ(q.own_edge_slope, 1.5 * r.own_edge_slope);
  EXPECT_EQ(q.n_radial, static_cast<int>(std::lround(1.5 * r.n_radial)));
  EXPECT_EQ(q.n_edge_near, 3 * r.n_edge_near);
  EXPECT_EQ(q.n_radial_near, 3 * r.n_radial_near);
  EXPECT_EQ(q.n_radial_near_out, 3 * r.n_radial_near_out);
  EXPECT_EQ(q.near_factor, r.near_factor);
  EXPECT_EQ(q.single_near_factor, r.single_near_factor);
  EXPECT_THROW(stokes::scale_orders(stokes::QuadratureOptions{}, {}), std::invalid_argument);
  EXPECT_THROW(stokes::scale_orders(r, {1.0, 0.0, 1.0}), std::invalid_argument);

  const Matrix3Xd x =
      geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.6, 0.7, 1.0));
  Matrix3Xd f(3, mesh.num_local());
  for (int m = 0; m < mesh.num_local(); ++m)
    f.col(m) = Vector3d(std::sin(x(0, m)), x(1, m) * x(2, m), std::exp(0.3 * x(0, m)));
  const Matrix3Xd nodes = op.single_layer(x, f);
  const stokes::BoundaryOperators ref(mesh, stokes::scale_orders(r, {3, 3, 3}));
  const Matrix3Xd at = ref.single_layer_at(x, f, x);
  const Matrix3Xd crude = op.single_layer_at(x, f, x);
  const double scale = nodes.cwiseAbs().maxCoeff();
  const double err_ref = (at - nodes).cwiseAbs().maxCoeff() / scale;
  const double err_crude = (crude - nodes).cwiseAbs().maxCoeff() / scale;
  std::printf("on-surface point path vs node path at the nodes: x3 orders %.2e, defaults %.2e\n",
              err_ref, err_crude);
  EXPECT_LT(err_ref, 1e-7);
}

// The operators keep their per-call buffers per thread across calls (boundary_integral.cpp,
// apply): a call must not see what an earlier call of another operator (other NE, NB, orders
// and far tiers) left there, results must not depend on the number of OpenMP threads, and two
// threads calling the same operator at once must each get the serial answer.
TEST(StokesApi, BuffersKeptAcrossCallsChangeNothing) {
  auto density = [](const Matrix3Xd& x) {
    Matrix3Xd f(3, x.cols());
    for (int m = 0; m < x.cols(); ++m)
      f.col(m) = Vector3d(std::sin(x(0, m)), x(1, m) * x(2, m), std::exp(0.3 * x(0, m)));
    return f;
  };
  geometry::Mesh ma(6, 8), mb(10, 6);
  const stokes::BoundaryOperators a(ma),
      b(mb, stokes::scale_orders(stokes::resolve_defaults(mb, {}), {2, 1, 2}));
  const Matrix3Xd xa = geometry::map_points(ma.reference(), geometry::ellipsoid_map(1.5, 0.8, 1.0));
  const Matrix3Xd xb = geometry::map_points(mb.reference(), geometry::ellipsoid_map(0.9, 1.2, 0.7));
  const Matrix3Xd fa = density(xa), fb = density(xb);
  const Matrix3Xd first = a.single_layer(xa, fa);
  const Matrix3Xd db = b.double_layer(xb, fb);  // other sizes through the same buffers
  const Matrix3Xd sb = b.single_layer(xb, fb);
  EXPECT_EQ((a.single_layer(xa, fa) - first).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((a.double_layer(xa, fa) - a.double_layer(xa, fa)).cwiseAbs().maxCoeff(), 0.0);

  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const Matrix3Xd one = a.single_layer(xa, fa);
  const Matrix3Xd one_b = b.single_layer(xb, fb);
  omp_set_num_threads(2);
  const Matrix3Xd two = a.single_layer(xa, fa);
  omp_set_num_threads(threads);
  EXPECT_EQ((one - first).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((two - first).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one_b - sb).cwiseAbs().maxCoeff(), 0.0);

  Matrix3Xd ta, tb;
  std::thread t1([&] { ta = a.single_layer(xa, fa); });
  std::thread t2([&] { tb = b.single_layer(xb, fb); });
  t1.join();
  t2.join();
  EXPECT_EQ((ta - first).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((tb - sb).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(db.cwiseAbs().maxCoeff(), 0.0);
}

// The thread cap (stokes/thread_cap.h): the team of a call is min(omp_get_max_threads, cap), the
// cap may come from another thread, and the sums do not depend on the team.
TEST(StokesApi, ThreadCapLimitsTheTeamAndChangesNothing) {
  geometry::Mesh mesh(6, 8);
  const stokes::BoundaryOperators op(mesh);
  const Matrix3Xd x =
      geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.4, 0.9, 1.0));
  Matrix3Xd f(3, x.cols());
  for (int m = 0; m < x.cols(); ++m) f.col(m) = Vector3d(x(1, m), std::cos(x(0, m)), 0.5);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(2);
  const Matrix3Xd free_sl = op.single_layer(x, f), free_dl = op.double_layer(x, f);
  std::thread([] { stokes::set_thread_cap(1); }).join();
  EXPECT_EQ(stokes::thread_cap(), 1);
  EXPECT_EQ(stokes::team_size(), 1);
  EXPECT_EQ((op.single_layer(x, f) - free_sl).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((op.double_layer(x, f) - free_dl).cwiseAbs().maxCoeff(), 0.0);
  stokes::set_thread_cap(8);
  EXPECT_EQ(stokes::team_size(), 2);  // the cap never raises the team
  stokes::set_thread_cap(0);
  EXPECT_EQ(stokes::team_size(), 2);
  omp_set_num_threads(threads);
}
