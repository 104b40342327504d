#include "geometry/smoothing.h"

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "geometry/surface.h"

namespace capflow::geometry {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;

SmoothingBasis tangent_basis(const Mesh& mesh, const Matrix3Xd& x) {
  const MatrixXd xd = x;
  return basis_from_tangents(geometry::d_xi(mesh, xd), geometry::d_eta(mesh, xd));
}

SmoothingBasis basis_from_tangents(const Matrix3Xd& t1, const Matrix3Xd& t2) {
  SmoothingBasis b;
  b.lower1 = t1;
  b.lower2 = t2;
  const Eigen::Index n = t1.cols();
  b.upper1.resize(3, n);
  b.upper2.resize(3, n);
  for (Eigen::Index m = 0; m < n; ++m) {
    const Vector3d a1 = t1.col(m), a2 = t2.col(m);
    const double g11 = a1.dot(a1), g12 = a1.dot(a2), g22 = a2.dot(a2);
    const double det = g11 * g22 - g12 * g12;
    b.upper1.col(m) = (g22 * a1 - g12 * a2) / det;
    b.upper2.col(m) = (g11 * a2 - g12 * a1) / det;
  }
  return b;
}

void average_coincident(const Mesh& mesh, Matrix3Xd* f) {
  for (const auto& cls : mesh.classes()) {
    if (cls.size() < 2) continue;
    Vector3d s = Vector3d::Zero();
    for (int m : cls) s += f->col(m);
    s /= static_cast<double>(cls.size());
    for (int m : cls) f->col(m) = s;
  }
}

namespace {

// M = E^1 (x) F_1 + E^2 (x) F_2 at local node m (3x3, M_ij = E^a_i F_a,j).
Matrix3d gradient_tensor(const SmoothingBasis& b, const Matrix3Xd& f1, const Matrix3Xd& f2,
                         int m) {
  return b.upper1.col(m) * f1.col(m).transpose() + b.upper2.col(m) * f2.col(m).transpose();
}

// Per-NB linear operator of stage 2 (depends only on the differentiation matrix).
// Element-local flat index i + nb*j. Constraints: the xi-slope at (0,j), (nb-1,j) and the
// eta-slope at (i,0), (i,nb-1) for i, j = 1..nb-2. Unknowns: the ring i or j in {1, nb-2}
// (inside the element) plus, for nb >= 6, the four nodes diagonally inside the ring corners,
// which makes the system square; for smaller nb it is solved in least squares.
struct EdgeSlopeSolver {
  struct Constraint {
    int node;       // flat index of the edge node
    int direction;  // 0: xi-slope, 1: eta-slope
    int sign_end;   // row of D used: 0 or nb-1
  };
  std::vector<Constraint> constraints;
  std::vector<int> unknown, known;
  MatrixXd solve_rhs, solve_known;  // u = solve_rhs * slopes - solve_known * known_values
};

const EdgeSlopeSolver& edge_slope_solver(int nb, const MatrixXd& d) {
  static std::mutex mu;
  static std::map<int, std::unique_ptr<EdgeSlopeSolver>> cache;
  std::lock_guard<std::mutex> lock(mu);
  auto& slot = cache[nb];
  if (slot) return *slot;
  auto s = std::make_unique<EdgeSlopeSolver>();
  auto flat = [nb](int i, int j) { return i + nb * j; };
  for (int j = 1; j <= nb - 2; ++j) {
    s->constraints.push_back({flat(0, j), 0, 0});
    s->constraints.push_back({flat(nb - 1, j), 0, nb - 1});
  }
  for (int i = 1; i <= nb - 2; ++i) {
    s->constraints.push_back({flat(i, 0), 1, 0});
    s->constraints.push_back({flat(i, nb - 1), 1, nb - 1});
  }
  std::vector<char> is_unknown(nb * nb, 0);
  for (int j = 1; j <= nb - 2; ++j)
    for (int i = 1; i <= nb - 2; ++i)
      if (i == 1 || i == nb - 2 || j == 1 || j == nb - 2) is_unknown[flat(i, j)] = 1;
  for (int k = 0; k < nb * nb; ++k) (is_unknown[k] ? s->unknown : s->known).push_back(k);
  // Slope rows over all nodal values.
  MatrixXd c = MatrixXd::Zero(s->constraints.size(), nb * nb);
  for (size_t r = 0; r < s->constraints.size(); ++r) {
    const auto& con = s->constraints[r];
    const int i0 = con.node % nb, j0 = con.node / nb;
    for (int k = 0; k < nb; ++k) {
      if (con.direction == 0)
        c(r, flat(k, j0)) += d(con.sign_end, k);
      else
        c(r, flat(i0, k)) += d(con.sign_end, k);
    }
  }
  MatrixXd cu(c.rows(), s->unknown.size()), ck(c.rows(), s->known.size());
  for (size_t k = 0; k < s->unknown.size(); ++k) cu.col(k) = c.col(s->unknown[k]);
  for (size_t k = 0; k < s->known.size(); ++k) ck.col(k) = c.col(s->known[k]);
  const Eigen::CompleteOrthogonalDecomposition<MatrixXd> cod(cu);
  s->solve_rhs = cod.pseudoInverse();
  s->solve_known = s->solve_rhs * ck;
  slot = std::move(s);
  return *slot;
}

}  // namespace

double max_gradient_jump(const Mesh& mesh, const SmoothingBasis& basis, const Matrix3Xd& f) {
  const MatrixXd fd = f;
  const Matrix3Xd f1 = geometry::d_xi(mesh, fd), f2 = geometry::d_eta(mesh, fd);
  double worst = 0;
  for (const auto& cls : mesh.classes()) {
    if (cls.size() < 2) continue;
    const Matrix3d m0 = gradient_tensor(basis, f1, f2, cls[0]);
    for (size_t k = 1; k < cls.size(); ++k)
      worst = std::max(worst, (gradient_tensor(basis, f1, f2, cls[k]) - m0).cwiseAbs().maxCoeff());
  }
  return worst;
}

namespace {
// Steps 2-3: the Lagrange derivatives f1, f2 of F and, at every shared node, the slopes from the
// averaged gradient tensor (elsewhere slope = own derivative); avg_of[m] the averaged tensor.
void prescribed_slopes(const Mesh& mesh, const SmoothingBasis& basis, const Matrix3Xd& f,
                       Matrix3Xd* f1, Matrix3Xd* f2, Matrix3Xd* slope1, Matrix3Xd* slope2,
                       std::vector<Matrix3d>* avg_of) {
  const MatrixXd fd = f;
  *f1 = geometry::d_xi(mesh, fd);
  *f2 = geometry::d_eta(mesh, fd);
  *slope1 = *f1;
  *slope2 = *f2;
  if (avg_of) avg_of->assign(mesh.num_local(), Matrix3d::Zero());
  for (const auto& cls : mesh.classes()) {
    if (cls.size() < 2) continue;
    Matrix3d avg = Matrix3d::Zero();
    for (int m : cls) avg += gradient_tensor(basis, *f1, *f2, m);
    avg /= static_cast<double>(cls.size());
    for (int m : cls) {
      if (avg_of) (*avg_of)[m] = avg;
      slope1->col(m) = avg.transpose() * basis.lower1.col(m);
      slope2->col(m) = avg.transpose() * basis.lower2.col(m);
    }
  }
}
}  // namespace

void hermite_derivatives(const Mesh& mesh, const SmoothingBasis& basis, const Matrix3Xd& f,
                         Matrix3Xd* d1, Matrix3Xd* d2) {
  const int nb = mesh.nb();
  Matrix3Xd l1, l2, slope1, slope2;
  std::vector<Matrix3d> avg_of;
  prescribed_slopes(mesh, basis, f, &l1, &l2, &slope1, &slope2, &avg_of);
  // w(xi) = prod_k (xi - xi_k); w'(xi_i) = prod_{k != i} (xi_i - xi_k).
  const Eigen::VectorXd& xi = mesh.nodes();
  Eigen::VectorXd wp(nb);
  for (int i = 0; i < nb; ++i) {
    double p = 1.0;
    for (int k = 0; k < nb; ++k)
      if (k != i) p *= xi[i] - xi[k];
    wp[i] = p;
  }
  // H(xi) = L(xi) + w(xi) [(1-xi)/2 c- + (1+xi)/2 c+],  c+- = (s+- - L'(+-1)) / w'(+-1);
  // at the nodes w = 0, so H'(xi_i) = L'(xi_i) + w'(xi_i) [(1-xi_i)/2 c- + (1+xi_i)/2 c+].
  auto hermite_line = [&](const Matrix3Xd& lag, const Matrix3Xd& slope, auto index, Matrix3Xd* out) {
    const Vector3d cm = (slope.col(index(0)) - lag.col(index(0))) / wp[0];
    const Vector3d cp = (slope.col(index(nb - 1)) - lag.col(index(nb - 1))) / wp[nb - 1];
    for (int k = 0; k < nb; ++k)
      out->col(index(k)) = lag.col(index(k)) + 0.5 * wp[k] * ((1 - xi[k]) * cm + (1 + xi[k]) * cp);
  };
  *d1 = l1;
  *d2 = l2;
  // 1. The element edges: along-edge derivatives from the corner slopes.
  for (int e = 0; e < mesh.ne(); ++e) {
    for (int i : {0, nb - 1}) hermite_line(l2, slope2, [&](int k) { return mesh.local(e, i, k); }, d2);
    for (int j : {0, nb - 1}) hermite_line(l1, slope1, [&](int k) { return mesh.local(e, k, j); }, d1);
  }
  // 2. Cross-edge slopes at edge-interior nodes, corrected by a rank-one term along the shared
  //    along-edge reference tangent E_a so that the tensor reproduces the edge's derivative g_a:
  //    F_c = M^T E_c + (g_a - M^T E_a)(E_a . E_c)/|E_a|^2. The corrected tensor
  //    M + (E_a/|E_a|^2) (x) (g_a - M^T E_a) is the same in every element sharing the node.
  for (int e = 0; e < mesh.ne(); ++e)
    for (int k = 1; k < nb - 1; ++k) {
      for (int i : {0, nb - 1}) {
        const int m = mesh.local(e, i, k);
        const Matrix3d mt = avg_of[m].transpose();
        const Vector3d ea = basis.lower2.col(m), ec = basis.lower1.col(m);
        slope1.col(m) = mt * ec + (d2->col(m) - mt * ea) * (ea.dot(ec) / ea.squaredNorm());
      }
      for (int j : {0, nb - 1}) {
        const int m = mesh.local(e, k, j);
        const Matrix3d mt = avg_of[m].transpose();
        const Vector3d ea = basis.lower1.col(m), ec = basis.lower2.col(m);
        slope2.col(m) = mt * ec + (d1->col(m) - mt * ea) * (ea.dot(ec) / ea.squaredNorm());
      }
    }
  // 3. Every interior grid line, across the element.
  for (int e = 0; e < mesh.ne(); ++e)
    for (int line = 1; line < nb - 1; ++line) {
      hermite_line(l1, slope1, [&](int k) { return mesh.local(e, k, line); }, d1);
      hermite_line(l2, slope2, [&](int k) { return mesh.local(e, line, k); }, d2);
    }
}

void smooth_first_order(const Mesh& mesh, const SmoothingBasis& basis, Matrix3Xd* f) {
  const int nb = mesh.nb();
  average_coincident(mesh, f);

  Matrix3Xd f1, f2, slope1, slope2;
  std::vector<Matrix3d> avg_of;
  prescribed_slopes(mesh, basis, *f, &f1, &f2, &slope1, &slope2, &avg_of);

  if (nb >= 4) {
    const MatrixXd& d = mesh.diff();
    // Stage 1: every element edge is a grid line whose end slopes (along the edge) are
    // prescribed at the two corners; re-solve the edge nodes next to the corners. This uses
    // only data on the edge itself, so neighbours sharing the edge compute the same result.
    const int p = 1, q = nb - 2;
    Eigen::Matrix2d sys;
    sys << d(0, p), d(0, q), d(nb - 1, p), d(nb - 1, q);
    const Eigen::Matrix2d inv = sys.inverse();
    auto solve_line = [&](auto index, const Vector3d& s_lo, const Vector3d& s_hi) {
      Vector3d r_lo = s_lo, r_hi = s_hi;
      for (int k = 0; k < nb; ++k) {
        if (k == p || k == q) continue;
        r_lo -= d(0, k) * f->col(index(k));
        r_hi -= d(nb - 1, k) * f->col(index(k));
      }
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector2d v = inv * Eigen::Vector2d(r_lo[c], r_hi[c]);
        (*f)(c, index(p)) = v[0];
        (*f)(c, index(q)) = v[1];
      }
    };
    for (int e = 0; e < mesh.ne(); ++e) {
      for (int j : {0, nb - 1}) {
        auto idx = [&](int k) { return mesh.local(e, k, j); };
        solve_line(idx, slope1.col(idx(0)), slope1.col(idx(nb - 1)));
      }
      for (int i : {0, nb - 1}) {
        auto idx = [&](int k) { return mesh.local(e, i, k); };
        solve_line(idx, slope2.col(idx(0)), slope2.col(idx(nb - 1)));
      }
    }
    average_coincident(mesh, f);
    // Stage 1 changed the along-edge derivatives near the corners. Correct the averaged tensor
    // at each edge-interior node by a rank-one term along the (shared) along-edge reference
    // tangent E_a so that it reproduces the new along-edge derivative g_a, then take the cross
    // slope from it: F_c = M^T E_c + (g_a - M^T E_a) (E_a . E_c)/|E_a|^2. The correction is the
    // same tensor in every element sharing the node, so the cross slopes stay consistent.
    {
      const MatrixXd fd1 = *f;
      const Matrix3Xd g1 = geometry::d_xi(mesh, fd1), g2 = geometry::d_eta(mesh, fd1);
      for (int e = 0; e < mesh.ne(); ++e)
        for (int j = 0; j < nb; ++j)
          for (int i = 0; i < nb; ++i) {
            const bool edge_i = (i == 0 || i == nb - 1), edge_j = (j == 0 || j == nb - 1);
            if (edge_i == edge_j) continue;  // interior node or corner
            const int m = mesh.local(e, i, j);
            const Matrix3d mt = avg_of[m].transpose();
            if (edge_i) {  // along-edge direction is eta
              const Vector3d ea = basis.lower2.col(m), ec = basis.lower1.col(m);
              slope1.col(m) = mt * ec + (g2.col(m) - mt * ea) * (ea.dot(ec) / ea.squaredNorm());
            } else {
              const Vector3d ea = basis.lower1.col(m), ec = basis.lower2.col(m);
              slope2.col(m) = mt * ec + (g1.col(m) - mt * ea) * (ea.dot(ec) / ea.squaredNorm());
            }
          }
    }
    // Stage 2: with the edges fixed, the values on the ring next to the edges are re-solved so
    // that the cross-edge slopes at all edge-interior nodes take their prescribed values.
    const EdgeSlopeSolver& solver = edge_slope_solver(nb, d);
    Eigen::VectorXd rhs(solver.constraints.size()), known(solver.known.size());
    for (int e = 0; e < mesh.ne(); ++e) {
      const int base = mesh.local(e, 0, 0);
      for (int c = 0; c < 3; ++c) {
        for (size_t r = 0; r < solver.constraints.size(); ++r) {
          const auto& con = solver.constraints[r];
          rhs[r] = (con.direction == 0 ? slope1 : slope2)(c, base + con.node);
        }
        for (size_t k = 0; k < solver.known.size(); ++k) known[k] = (*f)(c, base + solver.known[k]);
        const Eigen::VectorXd u = solver.solve_rhs * rhs - solver.solve_known * known;
        for (size_t k = 0; k < solver.unknown.size(); ++k) (*f)(c, base + solver.unknown[k]) = u[k];
      }
    }
  }
  average_coincident(mesh, f);
}

}  // namespace capflow::capsule
