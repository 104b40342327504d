#include "stokes/own_rules.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <string>

#include "geometry/shapes.h"
#include "spectral/spectral.h"
#include "stokes/boundary_integral.h"
#include "stokes/line_sums.h"

namespace capflow::stokes {

using Eigen::Matrix3Xd;
using Eigen::Vector3d;
using Eigen::VectorXd;

OwnRules::OwnRules(const geometry::Mesh& mesh, const QuadratureOptions& opt,
                   const VectorXd& prod_w) {
  const int nb = mesh.nb();
  const VectorXd& xi = mesh.nodes();
  canon_rule_.assign(nb * nb, -1);
  canon_sym_.assign(nb * nb, 0);
  canon_perm_.assign(8, std::vector<int>(nb * nb));
  for (int sym = 0; sym < 8; ++sym)
    for (int b = 0; b < nb; ++b)
      for (int a = 0; a < nb; ++a) {
        const int al = (sym & 4) ? b : a, be = (sym & 4) ? a : b;
        const int i = (sym & 1) ? nb - 1 - al : al, j = (sym & 2) ? nb - 1 - be : be;
        canon_perm_[sym][a + nb * b] = i + nb * j;
      }
  std::map<int, spectral::Rule> gauss;
  auto gl = [&gauss](int n) -> const spectral::Rule& {
    auto it = gauss.find(n);
    if (it == gauss.end()) it = gauss.emplace(n, spectral::gauss_legendre(n)).first;
    return it->second;
  };
  // own radial rule: graded inner panel [0, own_split] (n_radial_inner points, scale
  // own_grading) and Gauss on [own_split, 1]; plain Gauss on [0, 1] when n_radial_inner = 0
  const bool graded = opt.n_radial_inner > 0;
  const double grade = graded ? opt.own_grading : 0.0;
  const double hu_own[4] = {grade, grade, grade, grade};
  auto make_rule = [&](int ic, int jc, int n_e, int n_r) {
    LineRule r;
    const RadialOpt ro{graded ? &gl(opt.n_radial_inner) : nullptr, &gl(n_r),
                       graded ? opt.own_split : 0.0, 1};
    // the edge order of a side by its sinh range (QuadratureOptions::own_edge_base); the
    // selection by own_tolerance chooses one order for every side
    const std::function<const spectral::Rule&(double)> by_range =
        [&](double range) -> const spectral::Rule& {
      const double n = std::ceil(nb * (opt.own_edge_base + opt.own_edge_slope * range));
      return gl(static_cast<int>(std::max(2.0, std::min<double>(n_e, n))));
    };
    const bool ranged = opt.own_edge_base > 0.0 && !(opt.own_tolerance > 0.0);
    polar_rule(xi[ic], xi[jc], hu_own, gl(n_e), gl(n_r), r, ro, ranged ? &by_range : nullptr);
    fill_bases(mesh, prod_w, r);
    return r;
  };

  // Own-rule selection (own_tolerance > 0): for every canonical node, the rule with the fewest
  // points among n_edge in {4, 6, .., 2 nb + 4} x n_radial in {nb - 2, .., nb + 8} whose
  // own-element single layer matches a high-order rule (3 nb, 2 nb + 4) to own_tolerance
  // (relative to the largest value) for the smooth density f = (1 + 0.3 x, 0.5 - 0.2 y
  // + 0.1 x z, cos z) on the discrete unit sphere and the ellipsoid (1.8, 0.7, 1.0), with the
  // node placed in elements 0, ne/2 and ne-1.
  struct Probe {
    Matrix3Xd x, f;
    std::vector<ChebElement> cheb;  // the single layer's element data
  };
  std::vector<Probe> probes;
  std::vector<int> probe_elems;
  for (int e = 0; e < mesh.ne(); ++e) probe_elems.push_back(e);
  Scratch sc;
  if (opt.own_tolerance > 0.0) {
    for (int g = 0; g < 2; ++g) {
      Probe pr;
      pr.x = g == 0
                 ? mesh.reference()
                 : geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.8, 0.7, 1.0));
      pr.f.resize(3, mesh.num_local());
      for (int m = 0; m < mesh.num_local(); ++m) {
        const Vector3d q = pr.x.col(m);
        pr.f.col(m) =
            Vector3d(1.0 + 0.3 * q[0], 0.5 - 0.2 * q[1] + 0.1 * q[0] * q[2], std::cos(q[2]));
      }
      const Eigen::MatrixXd C = spectral::chebyshev_matrix(xi);
      pr.cheb.resize(mesh.ne());
      for (int e = 0; e < mesh.ne(); ++e)
        chebyshev_element(nb, 0, 6, C, pr.x, &pr.f, e * nb * nb, pr.cheb[e]);
      probes.push_back(std::move(pr));
    }
    size_scratch(sc, nb, 0);
  }
  const NodalBasis basis{xi.data(), prod_w.data(), mesh.diff().data()};
  auto own_values = [&](const LineRule& r, int ic, int jc) {
    std::vector<double> v;
    size_lines(sc, nb, r.nl());
    for (const Probe& pr : probes)
      for (int e : probe_elems) {
        const Vector3d x0 = pr.x.col(mesh.local(e, ic, jc));
        double acc[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        load_chebyshev(nb, 6, pr.cheb[e], 0, sc);
        line_sum<Mode::Single>(nb, 6, r, basis, 1.0, x0, Vector3d::Zero(), sc, acc);
        load_element(nb, 6, pr.x, &pr.f, e * nb * nb, nullptr, sc);
        v.insert(v.end(), acc, acc + 3);
        double acc2[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        line_sum<Mode::DoubleNormal>(nb, 3, r, basis, 1.0, x0, Vector3d::Zero(), sc, acc2);
        v.insert(v.end(), acc2, acc2 + 9);
      }
    return v;
  };
  std::vector<std::pair<int, int>> cands;  // (n_e, n_r), by n_e * n_r
  for (int n_r = std::max(2, nb - 2); n_r <= nb + 8; ++n_r)
    for (int n_e : {6, 8, 10, 12, 14, 16, 20, 24, 2 * nb + 4})
      if (n_e <= 2 * nb + 4 && (cands.empty() || cands.back() != std::make_pair(n_e, n_r)))
        cands.emplace_back(n_e, n_r);
  std::stable_sort(cands.begin(), cands.end(), [](const auto& a, const auto& b) {
    return a.first * a.second < b.first * b.second;
  });

  // The selection depends only on the mesh type and the options: cache it process-wide.
  static std::mutex cache_mutex;
  static std::map<std::string, std::map<int, std::pair<int, int>>> cache;
  const std::string cache_key = std::to_string(mesh.ne()) + "/" + std::to_string(nb) + "/" +
                                std::to_string(static_cast<int>(mesh.map())) + "/" +
                                std::to_string(opt.own_tolerance) + "/" +
                                std::to_string(opt.n_edge) + "/" + std::to_string(opt.n_radial);
  std::map<int, std::pair<int, int>> chosen;
  if (opt.own_tolerance > 0.0) {
    std::lock_guard<std::mutex> lock(cache_mutex);
    auto it = cache.find(cache_key);
    if (it != cache.end()) chosen = it->second;
  }
  const bool cached = !chosen.empty();
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
        LineRule r;
        if (cached) {
          const auto& c = chosen.at(key);
          r = make_rule(ic, jc, c.first, c.second);
        } else if (opt.own_tolerance > 0.0) {
          const std::vector<double> ref = own_values(make_rule(ic, jc, 3 * nb, 2 * nb + 4), ic, jc);
          double scale = 0;
          for (double v : ref) scale = std::max(scale, std::abs(v));
          bool found = false;
          for (const auto& c : cands) {
            LineRule trial = make_rule(ic, jc, c.first, c.second);
            const std::vector<double> v = own_values(trial, ic, jc);
            double err = 0;
            for (size_t q = 0; q < v.size(); ++q) err = std::max(err, std::abs(v[q] - ref[q]));
            if (err <= opt.own_tolerance * scale) {
              r = std::move(trial);
              chosen[key] = c;
              found = true;
              break;
            }
          }
          if (!found) {
            r = make_rule(ic, jc, opt.n_edge, opt.n_radial);
            chosen[key] = {opt.n_edge, opt.n_radial};
          }
        } else {
          r = make_rule(ic, jc, opt.n_edge, opt.n_radial);
        }
        it = key_to_rule.emplace(key, static_cast<int>(rules_.size())).first;
        rules_.push_back(std::move(r));
      }
      canon_rule_[i + nb * j] = it->second;
      canon_sym_[i + nb * j] = (fi ? 1 : 0) | (fj ? 2 : 0) | (sw ? 4 : 0);
    }
  if (opt.own_tolerance > 0.0 && !cached) {
    std::lock_guard<std::mutex> lock(cache_mutex);
    cache.emplace(cache_key, chosen);
  }
  make_row_bases(mesh, prod_w);
}

// The ray nodes shared by every rule (ray_nodes_ stays 0 if two rules differ) and the bases
// across the lines of each node index.
void OwnRules::make_row_bases(const geometry::Mesh& mesh, const VectorXd& prod_w) {
  std::vector<double> u;
  for (const LineRule& r : rules_)
    for (int l = 0; l < r.nl(); ++l) {
      const int q = r.radial[l];
      if (q >= static_cast<int>(u.size())) u.resize(q + 1, -1.0);
      if (u[q] < 0.0) u[q] = r.scale[l];
      if (u[q] != r.scale[l]) return;
    }
  for (double v : u)
    if (v < 0.0) return;
  const int nb = mesh.nb(), nr = static_cast<int>(u.size());
  const VectorXd& xi = mesh.nodes();
  std::vector<double> c(2 * nr);
  Eigen::MatrixXd L(2 * nr, nb), dL(2 * nr, nb);
  for (int i = 0; i < nb; ++i) {
    for (int side = 0; side < 2; ++side)
      for (int q = 0; q < nr; ++q)  // as polar_rule places the lines of a node at xi[i]
        c[side * nr + q] = xi[i] + u[q] * ((side ? 1.0 : -1.0) - xi[i]);
    spectral::lagrange_bases(xi, prod_w, c.data(), 2 * nr, L.data(), dL.data(), L.rows());
    row_bases_.push_back(L.transpose());
    row_derivs_.push_back(dL.transpose());
  }
  ray_nodes_ = nr;
}

long OwnRules::points() const {
  long n = 0;
  for (const LineRule& r : rules_) n += r.np();
  return n;
}

int OwnRules::max_lines() const {
  int n = 0;
  for (const LineRule& r : rules_) n = std::max(n, r.nl());
  return n;
}

}  // namespace capflow::stokes
