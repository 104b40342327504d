// Geometry: element divisions, coincidence classes, mirror maps, differential geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "geometry/surface.h"

using namespace capflow::geometry;

namespace {
constexpr double kPi = 3.14159265358979323846;

double max_mean_curvature_error_sphere(int ne, int nb, ElementMap map) {
  const Mesh mesh(ne, nb, map);
  const SurfaceGeometry g = compute_geometry(mesh, mesh.reference());
  return (g.mean_curvature.array() - 1.0).abs().maxCoeff();
}

// Every node's mirror image in each plane x_k = 0 is the node at the reflected position, the
// maps are involutions, and they map elements onto the mirror elements.
void expect_mirror_images(const Mesh& mesh) {
  const int nn = mesh.nodes_per_element();
  for (int k = 0; k < 3; ++k) {
    const auto& mir = mesh.mirror(k);
    for (int m = 0; m < mesh.num_local(); ++m) {
      Vector3d p = mesh.reference().col(m);
      p[k] = -p[k];
      ASSERT_LT((mesh.reference().col(mir[m]) - p).norm(), 1e-12);
      ASSERT_EQ(mir[mir[m]], m);
      ASSERT_EQ(mir[m] / nn, mesh.mirror_element(m / nn, k));
    }
  }
}

// locate inverts sphere_point at interior parameters of every element.
void expect_locate_round_trip(const Mesh& mesh) {
  for (int e = 0; e < mesh.ne(); ++e)
    for (double xi : {-0.7, 0.1, 0.95})
      for (double eta : {-0.9, 0.4}) {
        const Mesh::Location at = mesh.locate(2.0 * mesh.sphere_point(e, xi, eta));
        ASSERT_EQ(at.e, e);
        EXPECT_NEAR(at.xi, xi, 1e-13);
        EXPECT_NEAR(at.eta, eta, 1e-13);
      }
}
}  // namespace

TEST(Geometry, RejectsBadDivisions) {
  EXPECT_THROW(Mesh(8, 10), std::invalid_argument);
  EXPECT_THROW(Mesh(6, 2), std::invalid_argument);
}

TEST(Geometry, CoincidenceClassesHaveTheRightValences) {
  for (int ne : {6, 10, 14}) {
    for (int nb = 4; nb <= 16; ++nb) {
      const Mesh mesh(ne, nb);
      std::map<size_t, int> count;
      for (const auto& c : mesh.classes()) {
        ++count[c.size()];
        // Members coincide; they belong to different elements.
        for (size_t k = 1; k < c.size(); ++k) {
          ASSERT_LT((mesh.reference().col(c[k]) - mesh.reference().col(c[0])).norm(), 1e-12);
          ASSERT_NE(c[k] / (nb * nb), c[0] / (nb * nb));
        }
        const Vector3d p = mesh.reference().col(c[0]).cwiseAbs();
        if (c.size() == 3) {  // cube corners
          EXPECT_NEAR(p.x(), 1 / std::sqrt(3.0), 1e-14);
          EXPECT_NEAR(p.y(), 1 / std::sqrt(3.0), 1e-14);
        }
        if (c.size() == 4) {  // a division line meets a cube edge: one coordinate is zero
                              // (NE=10) or the division angle (NE=14)
          const int zero = (p.minCoeff() < 1e-14) ? 1 : 0;
          EXPECT_TRUE(zero == 1 || ne == 14);
        }
      }
      // Distinct classes are distinct points (no missed coincidences).
      double min_sep = 1e9;
      const auto& cls = mesh.classes();
      for (size_t a = 0; a < cls.size(); ++a)
        for (size_t b = a + 1; b < cls.size(); ++b)
          min_sep = std::min(
              min_sep,
              (mesh.reference().col(cls[a][0]) - mesh.reference().col(cls[b][0])).squaredNorm());
      EXPECT_GT(std::sqrt(min_sep), 1e-4);
      const int split_points = (ne == 6) ? 0 : (ne == 10 ? 4 : 8);
      EXPECT_EQ(count[1], ne * (nb - 2) * (nb - 2)) << ne << " " << nb;
      EXPECT_EQ(count[3], 8);
      EXPECT_EQ(count[4], split_points);
      // Euler: edges of the element graph, each with nb-2 interior shared nodes.
      const int edges = 2 * ne;  // quadrilateral mesh of the sphere: E = 2 F
      EXPECT_EQ(count[2], edges * (nb - 2)) << ne << " " << nb;
      EXPECT_EQ(mesh.num_unique(), static_cast<int>(cls.size()));
    }
  }
}

TEST(Geometry, MirrorMapsReflectPositions) {
  for (int ne : {6, 10, 14}) {
    for (int nb = 4; nb <= 16; nb += 3) expect_mirror_images(Mesh(ne, nb));
  }
}

TEST(Geometry, SphereNormalsOutwardAndCurvatures) {
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 14);
    const SurfaceGeometry g = compute_geometry(mesh, mesh.reference());
    for (int m = 0; m < mesh.num_local(); ++m) {
      ASSERT_GT(g.n.col(m).dot(mesh.reference().col(m)), 0.9999);
      ASSERT_NEAR(g.gaussian_curvature[m], 1.0, 1e-3);
    }
  }
}

TEST(Geometry, SphereMeanCurvatureConvergesExponentially) {
  for (int ne : {6, 10, 14}) {
    double e8 = max_mean_curvature_error_sphere(ne, 8, ElementMap::Equiangular);
    double e12 = max_mean_curvature_error_sphere(ne, 12, ElementMap::Equiangular);
    double e16 = max_mean_curvature_error_sphere(ne, 16, ElementMap::Equiangular);
    EXPECT_LT(e12, e8 / 30) << ne;
    EXPECT_LT(e16, e12 / 30) << ne;
  }
  EXPECT_LE(max_mean_curvature_error_sphere(6, 14, ElementMap::Equiangular), 1e-4);
  // The equiangular parametrisation beats the radial (gnomonic) one by orders of magnitude.
  EXPECT_GT(max_mean_curvature_error_sphere(6, 14, ElementMap::Radial),
            100 * max_mean_curvature_error_sphere(6, 14, ElementMap::Equiangular));
}

TEST(Geometry, SphereAreaAndVolume) {
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 14);
    const QuadratureSurface q = sample_gauss(mesh, mesh.reference(), 18);
    double area = q.w.sum(), vol = 0;
    for (int k = 0; k < q.x.cols(); ++k) vol += q.x.col(k).dot(q.n.col(k)) * q.w[k] / 3;
    EXPECT_NEAR(area / (4 * kPi), 1.0, 1e-10) << ne;
    EXPECT_NEAR(vol / (4 * kPi / 3), 1.0, 1e-10) << ne;
  }
}

TEST(Geometry, NodalDerivativesMatchFiniteDifferencesOfTheExactMap) {
  // t_a from the differentiation matrix vs central differences of the analytic sphere map.
  const Mesh mesh(10, 16);
  const Matrix3Xd x = map_points(mesh.reference(), ellipsoid_map(1.3, 0.8, 1.1));
  const SurfaceGeometry g = compute_geometry(mesh, x);
  const double h = 1e-5;
  double worst = 0;
  for (int e = 0; e < mesh.ne(); ++e)
    for (int j = 0; j < 16; j += 5)
      for (int i = 0; i < 16; i += 3) {
        const double s = mesh.nodes()[i], t = mesh.nodes()[j];
        auto f = [&](double a, double b) {
          Vector3d p = mesh.sphere_point(e, a, b);
          return Vector3d(1.3 * p.x(), 0.8 * p.y(), 1.1 * p.z());
        };
        const Vector3d fd1 = (f(s + h, t) - f(s - h, t)) / (2 * h);
        const Vector3d fd2 = (f(s, t + h) - f(s, t - h)) / (2 * h);
        const int m = mesh.local(e, i, j);
        worst = std::max(worst, (g.t1.col(m) - fd1).norm());
        worst = std::max(worst, (g.t2.col(m) - fd2).norm());
      }
  EXPECT_LT(worst, 1e-8);
}

TEST(Geometry, ElementEvaluatorDerivativesMatchFiniteDifferences) {
  const Mesh mesh(14, 12);
  const Matrix3Xd x = map_points(mesh.reference(), lamellar_map());
  const ElementEvaluator ev(mesh, x);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.95, 0.95);
  const double h = 1e-4;
  for (int k = 0; k < 50; ++k) {
    const int e = k % mesh.ne();
    const double s = u(rng), t = u(rng);
    const SurfacePoint p = ev.eval(e, s, t);
    const SurfacePoint ps = ev.eval(e, s + h, t), ms = ev.eval(e, s - h, t);
    const SurfacePoint pt = ev.eval(e, s, t + h), mt = ev.eval(e, s, t - h);
    const double tol = 1e-6 * (1 + p.xs.norm() + p.xt.norm());
    EXPECT_LT((p.xs - (ps.x - ms.x) / (2 * h)).norm(), tol);
    EXPECT_LT((p.xt - (pt.x - mt.x) / (2 * h)).norm(), tol);
    EXPECT_LT((p.xss - (ps.xs - ms.xs) / (2 * h)).norm(), 1e2 * tol);
    EXPECT_LT((p.xst - (pt.xs - mt.xs) / (2 * h)).norm(), 1e2 * tol);
    EXPECT_LT((p.xst - (ps.xt - ms.xt) / (2 * h)).norm(), 1e2 * tol);
    EXPECT_LT((p.xtt - (pt.xt - mt.xt) / (2 * h)).norm(), 1e2 * tol);
  }
  // At a node the evaluator reproduces the node and the nodal derivative exactly.
  const SurfaceGeometry g = compute_geometry(mesh, x);
  const int m = mesh.local(3, 4, 7);
  const SurfacePoint p = ev.eval(3, mesh.nodes()[4], mesh.nodes()[7]);
  EXPECT_LT((p.x - x.col(m)).norm(), 1e-14);
  EXPECT_LT((p.xs - g.t1.col(m)).norm(), 1e-11);
  EXPECT_LT((p.xtt - g.x22.col(m)).norm(), 1e-9);
}

TEST(Geometry, EllipsoidMeanCurvatureMatchesClosedForm) {
  for (int ne : {6, 10, 14}) {
    const Mesh mesh(ne, 16);
    const Matrix3Xd x = map_points(mesh.reference(), ellipsoid_map(1.8, 0.7, 1.0));
    const SurfaceGeometry g = compute_geometry(mesh, x);
    double err = 0;
    for (int m = 0; m < mesh.num_local(); ++m)
      err = std::max(
          err, std::abs(g.mean_curvature[m] - ellipsoid_mean_curvature(1.8, 0.7, 1.0, x.col(m))));
    EXPECT_LT(err, 1e-5) << ne;
  }
}

TEST(Geometry, LocateInvertsSpherePoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (ElementMap map : {ElementMap::Equiangular, ElementMap::Radial})
    for (int ne : {6, 10, 14}) {
      const Mesh mesh(ne, 5, map);
      double worst = 0;
      for (int e = 0; e < ne; ++e)
        for (int k = 0; k < 50; ++k) {
          const double xi = 0.999 * u(rng), eta = 0.999 * u(rng);
          const Mesh::Location at = mesh.locate(3.0 * mesh.sphere_point(e, xi, eta));
          ASSERT_EQ(at.e, e);
          worst = std::max({worst, std::abs(at.xi - xi), std::abs(at.eta - eta)});
        }
      EXPECT_LT(worst, 1e-13) << "ne " << ne;
      // Edge and corner points (shared by 2-4 elements) go to an element that holds them.
      for (int e = 0; e < ne; ++e)
        for (double xi : {-1.0, 1.0})
          for (double eta : {-1.0, 0.3, 1.0}) {
            const Vector3d p = mesh.sphere_point(e, xi, eta);
            const Mesh::Location at = mesh.locate(p);
            EXPECT_LT((mesh.sphere_point(at.e, at.xi, at.eta) - p).norm(), 1e-14);
          }
    }
  EXPECT_THROW(Mesh(6, 5).locate(Vector3d::Zero()), std::invalid_argument);
}

namespace {
// A smooth non-symmetric deformation of the material points X of the unit sphere.
Vector3d deformed(const Vector3d& X) {
  return Vector3d(1.4 * X.x() + 0.2 * X.y() * X.z(), 0.8 * X.y() + 0.1 * X.x() * X.x(),
                  0.9 * X.z() - 0.15 * X.x() * X.y() + 0.05);
}
Matrix3Xd deformed_nodes(const Mesh& mesh) {
  Matrix3Xd x(3, mesh.num_local());
  for (int m = 0; m < mesh.num_local(); ++m) x.col(m) = deformed(mesh.reference().col(m));
  return x;
}
}  // namespace

TEST(Geometry, ResampleIsExactOnTheSameMeshAndOnElementPolynomials) {
  for (int ne : {6, 10, 14}) {
    const Mesh coarse(ne, 6), fine(ne, 12);
    const Matrix3Xd x = deformed_nodes(coarse);
    // Onto the same mesh: the identity.
    EXPECT_LT((resample_surface(coarse, x, coarse) - x).cwiseAbs().maxCoeff(), 1e-13) << ne;
    // The coarse interpolant is a degree-5 polynomial on each element: NB=12 represents it
    // exactly, so coarse -> fine -> coarse returns x, and the fine interpolant equals the coarse
    // one everywhere.
    const Matrix3Xd xf = resample_surface(coarse, x, fine);
    EXPECT_LT((resample_surface(fine, xf, coarse) - x).cwiseAbs().maxCoeff(), 1e-12) << ne;
    const ElementEvaluator ec(coarse, x), ef(fine, xf);
    double worst = 0;
    for (int e = 0; e < ne; ++e)
      for (double s : {-0.77, 0.1, 0.93})
        for (double t : {-0.4, 0.55})
          worst = std::max(worst, (ec.eval(e, s, t).x - ef.eval(e, s, t).x).norm());
    EXPECT_LT(worst, 1e-12) << ne;
    // Coincident nodes of the target are identical.
    for (const auto& c : fine.classes())
      for (int m : c) ASSERT_EQ((xf.col(m) - xf.col(c.front())).norm(), 0.0);
  }
}

TEST(Geometry, ResampleAcrossDivisionsConvergesSpectrally) {
  // NE=6 -> NE=14 (the element edges do not coincide): the error against the exact map at the
  // target nodes is the source's interpolation error, falling exponentially with the source NB.
  const Mesh target(14, 12);
  const Matrix3Xd exact = deformed_nodes(target);
  std::vector<double> err;
  for (int nb : {6, 9, 12, 15}) {
    const Mesh source(6, nb);
    err.push_back(
        (resample_surface(source, deformed_nodes(source), target) - exact).cwiseAbs().maxCoeff());
    std::printf("NE=6 NB=%d -> NE=14 NB=12: max error %.2e\n", nb, err.back());
  }
  for (size_t k = 1; k < err.size(); ++k) EXPECT_LT(err[k], 0.1 * err[k - 1]);
  EXPECT_LT(err.back(), 1e-6);
  EXPECT_THROW(resample_surface(Mesh(6, 6), Matrix3Xd::Zero(3, 10), target), std::invalid_argument);
}

TEST(Geometry, BoxDivisionTilesTheSphereWithUnitSquareFaces) {
  // The parallelepiped projection (Division::Box): same topology as the cube divisions, nodes
  // on the unit sphere, coincidences, mirrors and locate as on the cube; the element edges lie
  // where the box's unit-square face regions meet.
  for (int ne : {6, 10, 14}) {
    const Vector3d box = ne == 10   ? Vector3d(2, 1, 1)
                         : ne == 14 ? Vector3d(1, 3, 1)
                                    : Vector3d(1, 1, 1);
    for (int nb : {5, 8}) {
      const Mesh mesh(ne, nb, ElementMap::Equiangular, Division::Box);
      const Mesh cube(ne, nb);
      EXPECT_EQ(mesh.division(), Division::Box);
      EXPECT_EQ((mesh.box() - box).norm(), 0.0);
      EXPECT_EQ(mesh.num_unique(), cube.num_unique()) << ne;
      for (int m = 0; m < mesh.num_local(); ++m)
        ASSERT_NEAR(mesh.reference().col(m).norm(), 1.0, 1e-14);
      std::map<size_t, int> count;
      for (const auto& c : mesh.classes()) {
        ++count[c.size()];
        for (size_t k = 1; k < c.size(); ++k)
          ASSERT_LT((mesh.reference().col(c[k]) - mesh.reference().col(c[0])).norm(), 1e-12);
        if (c.size() == 3) {  // box corners
          EXPECT_LT((mesh.reference().col(c[0]).cwiseAbs() - box.normalized()).norm(), 1e-14);
        }
        if (c.size() == 4 && ne == 14) {  // row boundaries at |y| = 1 on the box
          const Vector3d p = mesh.reference().col(c[0]).cwiseAbs();
          EXPECT_NEAR(p.y() / std::max(p.x(), p.z()), 1.0, 1e-14);
        }
      }
      EXPECT_EQ(count[3], 8);
      EXPECT_EQ(count[4], ne == 6 ? 0 : ne == 10 ? 4 : 8);
      EXPECT_EQ(count[2], 2 * ne * (nb - 2));
      expect_mirror_images(mesh);
      expect_locate_round_trip(mesh);
    }
  }
  // NE=10: the caps +-x span 2 atan(1/2) (53 degrees) in each direction, not 90.
  const Mesh m10(10, 6, ElementMap::Equiangular, Division::Box);
  for (int e = 0; e < 10; ++e) {
    if (m10.patches()[e].axis != 0) continue;
    const Vector3d corner = m10.sphere_point(e, 1.0, 1.0);
    EXPECT_NEAR(std::abs(corner.y() / corner.x()), 0.5, 1e-14);
    EXPECT_NEAR(std::abs(corner.z() / corner.x()), 0.5, 1e-14);
  }
  // The sphere is resolved spectrally on the box divisions too (NE=14's elongated outer rows
  // and small caps resolve it less well than the cube's equal-angle rows).
  for (int ne : {10, 14}) {
    const Mesh a(ne, 14, ElementMap::Equiangular, Division::Box);
    const QuadratureSurface q = sample_gauss(a, a.reference(), 18);
    double vol = 0;
    for (int k = 0; k < q.x.cols(); ++k) vol += q.x.col(k).dot(q.n.col(k)) * q.w[k] / 3;
    EXPECT_NEAR(q.w.sum() / (4 * kPi), 1.0, 1e-9) << ne;
    EXPECT_NEAR(vol / (4 * kPi / 3), 1.0, 1e-9) << ne;
    double err[3];
    for (int k = 0; k < 3; ++k) {
      const Mesh b(ne, 8 + 4 * k, ElementMap::Equiangular, Division::Box);
      const SurfaceGeometry g = compute_geometry(b, b.reference());
      err[k] = (g.mean_curvature.array() - 1.0).abs().maxCoeff();
    }
    std::printf("box NE=%d: max |H - 1| at NB=8, 12, 16: %.2e %.2e %.2e\n", ne, err[0], err[1],
                err[2]);
    EXPECT_LT(err[1], err[0] / 10) << ne;
    EXPECT_LT(err[2], err[1] / 10) << ne;
  }
}

TEST(Geometry, DiagonalDivisionIsTheCubeTurnedAboutZ) {
  // Division::Diagonal: every node is the cube's node turned by 45 degrees about z; the +-x and
  // +-y axes pierce element edges (midpoints of the edges shared by two side faces), the +-z
  // axes face centres; coincidences, mirrors and locate hold as on the cube; only NE=6.
  EXPECT_THROW(Mesh(10, 8, ElementMap::Equiangular, Division::Diagonal), std::invalid_argument);
  EXPECT_THROW(Mesh(14, 8, ElementMap::Equiangular, Division::Diagonal), std::invalid_argument);
  const double c = std::sqrt(0.5);
  for (int nb : {5, 8, 9}) {
    const Mesh mesh(6, nb, ElementMap::Equiangular, Division::Diagonal);
    const Mesh cube(6, nb);
    EXPECT_EQ(mesh.division(), Division::Diagonal);
    EXPECT_EQ(mesh.num_unique(), cube.num_unique());
    for (int m = 0; m < mesh.num_local(); ++m) {
      const Vector3d p = cube.reference().col(m);
      const Vector3d turned(c * (p.x() - p.y()), c * (p.x() + p.y()), p.z());
      ASSERT_LT((mesh.reference().col(m) - turned).norm(), 1e-15);
    }
    for (size_t k = 0; k < mesh.classes().size(); ++k)
      ASSERT_EQ(mesh.classes()[k], cube.classes()[k]);
    // The +x axis: on an edge (a node class of two elements when nb is odd: the edge midpoint).
    for (const Vector3d& axis : {Vector3d(1, 0, 0), Vector3d(0, -1, 0), Vector3d(0, 0, 1)}) {
      int hits = 0;
      for (const auto& cls : mesh.classes())
        if ((mesh.reference().col(cls.front()) - axis).norm() < 1e-14) {
          ++hits;
          EXPECT_EQ(cls.size(), axis.z() != 0 ? 1u : 2u) << axis.transpose();
        }
      EXPECT_EQ(hits, nb % 2) << axis.transpose() << " nb " << nb;
    }
    expect_mirror_images(mesh);
    expect_locate_round_trip(mesh);
    for (int e = 0; e < 6; ++e) {
      for (double xi : {-1.0, 1.0}) {  // edge points go to an element holding them
        const Vector3d p = mesh.sphere_point(e, xi, 0.3);
        const Mesh::Location at = mesh.locate(p);
        EXPECT_LT((mesh.sphere_point(at.e, at.xi, at.eta) - p).norm(), 1e-14);
      }
    }
  }
  // Area, volume and curvature of the sphere as on the cube (the turn is a rigid motion).
  const Mesh d14(6, 14, ElementMap::Equiangular, Division::Diagonal);
  const QuadratureSurface q = sample_gauss(d14, d14.reference(), 18);
  double vol = 0;
  for (int k = 0; k < q.x.cols(); ++k) vol += q.x.col(k).dot(q.n.col(k)) * q.w[k] / 3;
  EXPECT_NEAR(q.w.sum() / (4 * kPi), 1.0, 1e-10);
  EXPECT_NEAR(vol / (4 * kPi / 3), 1.0, 1e-10);
  // the same error (9.4e-6) to the rounding of the turned nodes through two differentiations
  // at NB=14 (~1e-12, more with FMA contraction)
  const SurfaceGeometry g = compute_geometry(d14, d14.reference());
  EXPECT_NEAR((g.mean_curvature.array() - 1.0).abs().maxCoeff(),
              max_mean_curvature_error_sphere(6, 14, ElementMap::Equiangular), 1e-10);
}

TEST(Geometry, ParametricDerivativesAreExactOnPolynomials) {
  // Row r of element e holds p(xi, eta) = c xi^a eta^b (a, b <= nb - 1, a different monomial
  // per row and element): d_xi and d_eta return c a xi^(a-1) eta^b and c b xi^a eta^(b-1) at
  // the nodes, for any number of rows.
  for (int nb : {4, 7, 10}) {
    const Mesh mesh(6, nb);
    const Eigen::VectorXd& s = mesh.nodes();
    for (int rows : {1, 3, 5}) {
      MatrixXd f(rows, mesh.num_local()), fx(rows, mesh.num_local()), fy(rows, mesh.num_local());
      for (int e = 0; e < mesh.ne(); ++e)
        for (int r = 0; r < rows; ++r) {
          const int a = (e + 2 * r) % nb, b = (3 * e + r + 1) % nb;
          const double c = 1.0 + 0.25 * r - 0.1 * e;
          for (int j = 0; j < nb; ++j)
            for (int i = 0; i < nb; ++i) {
              const int m = mesh.local(e, i, j);
              const double xi = s[i], eta = s[j];
              f(r, m) = c * std::pow(xi, a) * std::pow(eta, b);
              fx(r, m) = a == 0 ? 0.0 : c * a * std::pow(xi, a - 1) * std::pow(eta, b);
              fy(r, m) = b == 0 ? 0.0 : c * b * std::pow(xi, a) * std::pow(eta, b - 1);
            }
        }
      EXPECT_LT((d_xi(mesh, f) - fx).cwiseAbs().maxCoeff(), 1e-11) << nb << " " << rows;
      EXPECT_LT((d_eta(mesh, f) - fy).cwiseAbs().maxCoeff(), 1e-11) << nb << " " << rows;
    }
  }
}
