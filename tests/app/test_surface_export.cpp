// The ParaView surface of a state (app/surface_export.h): the nodes themselves at n = NB, the
// interpolant at n Gauss-Lobatto points (exact for fields linear in the positions, spectrally
// accurate on the sphere: radius, normal and mean curvature), and the welded file's point count
// from the division's topology (element edges and corners once).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/frames.h"
#include "app/surface_export.h"
#include "capsule/capsule.h"
#include "geometry/mesh.h"
#include "geometry/surface.h"
#include "membrane/bending.h"
#include "output/vtk.h"

namespace fs = std::filesystem;
using capflow::app::NodalState;
using capflow::app::surface_export;
using capflow::geometry::Mesh;

namespace {

capflow::render::Snapshot snapshot_of(const Mesh& mesh, const Eigen::Matrix3Xd& x) {
  capflow::render::Snapshot sn;
  sn.ne = mesh.ne();
  sn.nb = mesh.nb();
  sn.x.assign(x.data(), x.data() + x.size());
  for (int k = 0; k < x.cols(); ++k) {  // "tensions" z and x - y: smooth nodal fields
    sn.tau1.push_back(x(2, k));
    sn.tau2.push_back(x(0, k) - x(1, k));
  }
  sn.time = 0.5;
  sn.ca = 0.2;
  return sn;
}

}  // namespace

TEST(SurfaceExport, AtTheNodeCountItWritesTheNodes) {
  const Mesh mesh(6, 7);
  const Eigen::Matrix3Xd x = mesh.reference();
  const capflow::render::Snapshot sn = snapshot_of(mesh, x);
  const capflow::output::VtkSurface v = surface_export(mesh, {&x, nullptr, &sn}, 7);
  ASSERT_EQ(v.x.size(), static_cast<size_t>(x.size()));
  for (int k = 0; k < x.cols(); ++k)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(v.x[3 * k + d], x(d, k));
  EXPECT_EQ(v.point_arrays.at("tau1").values, sn.tau1);
  EXPECT_EQ(v.point_arrays.count("velocity"), 0u);
  EXPECT_EQ(v.time, 0.5);
  EXPECT_EQ(v.field_scalars.at("ca"), 0.2);
}

// With bending, the energy density (kappa_b / 2)(2H - c0)^2: 2 kappa_b on the unit sphere (c0 = 0).
TEST(SurfaceExport, BendingEnergyDensityWhenGiven) {
  const Mesh mesh(6, 12);
  const Eigen::Matrix3Xd x = mesh.reference();
  const capflow::render::Snapshot sn = snapshot_of(mesh, x);
  capflow::membrane::BendingOptions o;
  o.modulus = 0.01;
  const capflow::membrane::Bending b(mesh, x, o);
  const Eigen::VectorXd w = b.energy_density(x);
  NodalState s{&x, nullptr, &sn, &w};
  const capflow::output::VtkSurface v = surface_export(mesh, s, 16);
  const std::vector<double>& values = v.point_arrays.at("bending_energy_density").values;
  ASSERT_EQ(values.size(), v.x.size() / 3);
  for (double value : values) EXPECT_NEAR(value, 0.02, 2e-4);
  EXPECT_EQ(surface_export(mesh, {&x, nullptr, &sn}, 16).point_arrays.count("bending_energy_density"),
            0u);
}

// A frame's snapshot carries the bending energy density when the capsule bends (2 Eb on the
// unit sphere with Helfrich bending, c0 = 0: what render.field "bending-energy" colours by),
// and no such array when it does not.
TEST(SurfaceExport, FrameSnapshotsCarryTheBendingEnergyDensity) {
  const Mesh mesh(6, 12);
  capflow::capsule::DynamicsOptions o;
  o.bending.modulus = 0.01;
  const capflow::capsule::Capsule bent(mesh, {}, capflow::capsule::Flow::simple_shear(), o);
  const capflow::render::Snapshot s =
      capflow::app::state_snapshot(bent, bent.positions(), 0, 0.1, "skalak", {});
  ASSERT_EQ(s.bending.size(), static_cast<size_t>(mesh.num_local()));
  for (double w : s.bending) EXPECT_NEAR(w, 0.02, 2e-4);
  const capflow::capsule::Capsule plain(mesh, {}, capflow::capsule::Flow::simple_shear());
  EXPECT_TRUE(
      capflow::app::state_snapshot(plain, plain.positions(), 0, 0.1, "skalak", {}).bending.empty());
}

TEST(SurfaceExport, UpsampledSurfaceIsTheInterpolant) {
  const Mesh mesh(10, 10);
  const Eigen::Matrix3Xd x = mesh.reference();
  Eigen::Matrix3d A;
  A << 0.3, -1.0, 0.2, 1.0, 0.1, 0.0, -0.4, 0.5, -0.4;
  const Eigen::Matrix3Xd u = A * x;  // linear in x: interpolates to A times the points
  const capflow::render::Snapshot sn = snapshot_of(mesh, x);
  const int n = 25;
  const capflow::output::VtkSurface v = surface_export(mesh, {&x, &u, &sn}, n);
  ASSERT_EQ(v.n, n);
  const std::vector<double>& vel = v.point_arrays.at("velocity").values;
  const std::vector<double>& nor = v.point_arrays.at("Normals").values;
  const std::vector<double>& H = v.point_arrays.at("mean_curvature").values;
  const std::vector<double>& t1 = v.point_arrays.at("tau1").values;
  double lin = 0, rad = 0, nrm = 0, curv = 0, fld = 0;
  for (long k = 0; k < v.num_points(); ++k) {
    const Eigen::Vector3d p(v.x[3 * k], v.x[3 * k + 1], v.x[3 * k + 2]);
    const Eigen::Vector3d q(vel[3 * k], vel[3 * k + 1], vel[3 * k + 2]);
    const Eigen::Vector3d m(nor[3 * k], nor[3 * k + 1], nor[3 * k + 2]);
    lin = std::max(lin, (q - A * p).norm());
    rad = std::max(rad, std::abs(p.norm() - 1.0));
    nrm = std::max(nrm, (m - p.normalized()).norm());  // outward unit normal of the sphere
    curv = std::max(curv, std::abs(H[k] - 1.0));
    fld = std::max(fld, std::abs(t1[k] - p.z()));  // z interpolated like the positions
  }
  EXPECT_LT(lin, 1e-13);
  EXPECT_LT(fld, 1e-14);
  // the NB=10 interpolant of the sphere between its nodes: spectral accuracy
  EXPECT_LT(rad, 1e-5);
  EXPECT_LT(nrm, 1e-4);
  // the mean curvature interpolated from its nodal values: no worse than at the nodes (x1.5)
  const double nodal =
      (capflow::geometry::compute_geometry(mesh, x).mean_curvature.array() - 1.0).abs().maxCoeff();
  EXPECT_LT(curv, 1.5 * nodal);
  EXPECT_LT(nodal, 1e-2);
  EXPECT_GT(rad, 0.0);  // the points are not only the nodes
  EXPECT_THROW(surface_export(mesh, {&x, &u, &sn}, 1), std::invalid_argument);
}

TEST(SurfaceExport, WeldedFileHasEachPointOnce) {
  // NE=10 (the box division: 20 edges, 12 corners): 10 (n-2)^2 + 20 (n-2) + 12 points; at NB=8
  // the node grid's 640 grid points are 492 distinct ones
  const fs::path d =
      fs::temp_directory_path() / ("capflow_surface_export_" + std::to_string(::getpid()));
  fs::create_directories(d);
  const Mesh mesh(10, 8);
  const Eigen::Matrix3Xd x = mesh.reference();
  const capflow::render::Snapshot sn = snapshot_of(mesh, x);
  for (int n : {8, 25}) {
    const capflow::output::VtkSurface v = surface_export(mesh, {&x, nullptr, &sn}, n);
    capflow::output::write_vtp((d / "s.vtp").string(), v);
    std::ifstream f(d / "s.vtp");
    std::stringstream all;
    all << f.rdbuf();
    const long unique = 10L * (n - 2) * (n - 2) + 20L * (n - 2) + 12;
    if (n == 8) {
      EXPECT_EQ(unique, 492);
    }
    EXPECT_NE(all.str().find("NumberOfPoints=\"" + std::to_string(unique) + "\""),
              std::string::npos)
        << "n " << n;
    const capflow::output::VtkSurface r = capflow::output::read_vtp((d / "s.vtp").string());
    EXPECT_EQ(r.n, n);
    EXPECT_EQ(r.num_points(), v.num_points());
  }
  fs::remove_all(d);
}
