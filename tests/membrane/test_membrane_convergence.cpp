// Validation tables for the membrane traction (docs/validation.md, Milestone 2b):
// convergence of f in NB, virtual work, force/torque balance, inflation of the sphere.
// Run: build-membrane/tests/membrane/test_membrane_convergence   (prints the tables)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "membrane_test_util.h"

namespace capflow::membrane {
namespace {

using geometry::Mesh;
using testing::all_laws;
using testing::label;

constexpr int kNe = 6;
const int kNbs[] = {8, 10, 12, 14, 16, 18, 20, 22, 24};

// f at fixed interior parameter points of every element: 3 x (ne * points).
MatrixXd interior_samples(const Mesh& mesh, const Matrix3Xd& f) {
  const double pts[][2] = {{0.3, -0.2}, {-0.55, 0.7}, {0.0, 0.0}};
  MatrixXd out(3, 3 * mesh.ne());
  for (int p = 0; p < 3; ++p)
    out.middleCols(p * mesh.ne(), mesh.ne()) =
        testing::eval_in_elements(mesh, MatrixXd(f), pts[p][0], pts[p][1]);
  return out;
}

MatrixXd traction_samples(int nb, const geometry::PointMap& map, std::shared_ptr<const Law> law) {
  const Mesh mesh(kNe, nb);
  const Membrane mem(mesh, mesh.reference(), law);
  return interior_samples(mesh, mem.traction(geometry::map_points(mesh.reference(), map)));
}

// Relative error max|f_NB - f_30| / max|f_30| at the interior points.
std::vector<double> convergence_row(const geometry::PointMap& map,
                                    std::shared_ptr<const Law> law) {
  const MatrixXd ref = traction_samples(30, map, law);
  const double scale = ref.colwise().norm().maxCoeff();
  std::vector<double> row;
  for (int nb : kNbs)
    row.push_back((traction_samples(nb, map, law) - ref).colwise().norm().maxCoeff() / scale);
  return row;
}

void print_header(const char* title) {
  std::printf("\n%s\n%-24s", title, "law \\ NB");
  for (int nb : kNbs) std::printf(" %8d", nb);
  std::printf("\n");
}
void print_row(const std::string& name, const std::vector<double>& row) {
  std::printf("%-24s", name.c_str());
  for (double v : row) std::printf(" %8.1e", v);
  std::printf("\n");
}
double at_nb(const std::vector<double>& row, int nb) {
  for (size_t k = 0; k < row.size(); ++k)
    if (kNbs[k] == nb) return row[k];
  return NAN;
}

TEST(MembraneValidation, TractionConvergesInNB) {
  struct Shape {
    const char* name;
    geometry::PointMap map;
  };
  const Shape shapes[] = {{"ellipsoid (1.2,0.9,1/1.08)", geometry::ellipsoid_map(1.2, 0.9, 1 / 1.08)},
                          {"ellipsoid (1.8,0.7,1.0)", geometry::ellipsoid_map(1.8, 0.7, 1.0)}};
  for (const Shape& s : shapes) {
    print_header((std::string("f relative error vs NB=30, interior points, ") + s.name).c_str());
    for (const auto& law : all_laws()) {
      const std::vector<double> row = convergence_row(s.map, law);
      print_row(label(*law), row);
      EXPECT_LT(row.back(), 1e-3 * row.front()) << label(*law);
    }
  }
}

}  // namespace
}  // namespace capflow::membrane
