// capflow figure (src/app/cmd_figure.cpp, src/app/figure_data.h) on small synthetic run
// directories written here: every figure kind is produced and non-empty, SVGs parse as XML
// (expat), the .dat sidecars hold exactly the CSV values they came from, 3-D views are rendered
// from the saved .vtp surface nearest in time, and a run without surface data gets the frame
// PNG nearest in time with a note saying so.
#include <expat.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/surface_files.h"
#include "figures/run_tables.h"
#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "output/png_writer.h"
#include "output/vtk.h"

namespace fs = std::filesystem;
namespace fig = capflow::figures;
namespace app = capflow::app;

namespace {

fs::path fresh_dir(const std::string& name) {
  const auto d =
      fs::temp_directory_path() / ("capflow_fig_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

void put(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::trunc) << text;
}

std::string g(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

double deformation(double t, double amp) {
  return amp * (1 - std::exp(-t));
}

// A synthetic run: D(t) = amp (1 - e^-t) on t = 0, 0.05, .., 2; steady states at four Ca;
// profiles (ellipses) and solid-colour frames at t = 0, 0.5, .., 2 (frame k <-> profile k);
// with `surfaces`, ellipsoid surfaces at t = 0, 1, 2 in vtk/ + surface.pvd.
void make_run(const fs::path& d, double amp, bool surfaces) {
  std::ostringstream ts;
  ts << "t,ca,D,L,S,W,Lc,Sc,Wc,area,volume,edge_curvature,tau_max,tau_min,inclination_deg,"
        "volume_drift,steps,wall_s\n";
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.05 * k, D = deformation(t, amp);
    ts << g(t) << ",0.45," << g(D) << "," << g(1 + D) << "," << g(1 - D) << "," << g(1 + 0.1 * D)
       << "," << g(1.02 * (1 + D)) << "," << g(0.98 * (1 - D)) << "," << g(1 + 0.12 * D) << ","
       << g(12.566 * (1 + 0.1 * D)) << ",4.18879," << g(1 + 5 * D) << "," << g(2 * D) << ","
       << g(-0.1 * D) << ",0,0," << k * 10 << ",0." << k << "\n";
  }
  put(d / "timeseries.csv", ts.str());
  std::ostringstream st;
  st << "ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min\n";
  for (double ca : {0.15, 0.3, 0.45, 0.6}) {
    const double D = amp * ca;
    st << g(ca) << "," << g(1 + D) << "," << g(1 - D) << "," << g(1 + 0.1 * D) << ","
       << g(1.02 * (1 + D)) << "," << g(0.98 * (1 - D)) << "," << g(1 + 0.12 * D) << "," << g(D)
       << "," << g(12.566 * (1 + 0.1 * D)) << "," << g(1 + 8 * D * D) << "," << g(3 * D) << ","
       << g(-0.1 * D) << "\n";
  }
  put(d / "steady.csv", st.str());
  fs::create_directories(d / "frames");
  for (int k = 0; k <= 4; ++k) {
    const double t = 0.5 * k, D = deformation(t, amp);
    std::ostringstream p;
    p << "plane,t,a,b\n";
    for (const char* plane : {"z", "y"})
      for (int i = 0; i < 48; ++i) {
        const double th = 2 * M_PI * i / 48;
        const double b = plane[0] == 'z' ? (1 - D) : (1 + 0.1 * D);
        p << plane << "," << g(t) << "," << g((1 + D) * std::cos(th)) << "," << g(b * std::sin(th))
          << "\n";
      }
    char name[64];
    std::snprintf(name, sizeof name, "profiles/profile_%06d.csv", k);
    put(d / name, p.str());
    std::vector<uint8_t> px(64 * 48 * 4);
    for (size_t i = 0; i < px.size(); i += 4) {
      px[i] = static_cast<uint8_t>(40 * k);
      px[i + 1] = 100;
      px[i + 2] = static_cast<uint8_t>(200 - 40 * k);
      px[i + 3] = 255;
    }
    std::snprintf(name, sizeof name, "frames/frame_%06d.png", k);
    capflow::output::write_png((d / name).string(), 64, 48, px.data());
  }
  if (surfaces) {
    fs::create_directories(d / "vtk");
    capflow::output::PvdCollection pvd((d / app::kSurfaceCollection).string());
    capflow::geometry::Mesh mesh(6, 9);  // odd NB: a node at each face centre
    for (int k = 0; k <= 2; ++k) {
      const double t = k, D = deformation(t, amp);
      const auto x = capflow::geometry::map_points(
          mesh.reference(), capflow::geometry::ellipsoid_map(1 + D, 1 - D, 1 + 0.1 * D));
      capflow::render::Snapshot s;
      s.ne = 6;
      s.nb = 9;
      s.time = t;
      s.ca = 0.45;
      s.diag.D = D;
      const int n = mesh.num_local();
      s.x.assign(x.data(), x.data() + 3 * n);
      for (int i = 0; i < n; ++i) {
        s.tau1.push_back(1 + x(0, i) * x(0, i));
        s.tau2.push_back(x(2, i));
      }
      s.diag.tau_max = *std::max_element(s.tau1.begin(), s.tau1.end());
      const std::string f = app::surface_file_name(k);
      capflow::output::write_vtp((d / f).string(), app::vtk_from_snapshot(s));
      pvd.add(t, f);
    }
  }
}

// The control of a Skalak C = 1 run in planar extension: the law and flow the paper reports
// steady states for (figures/references.h).
const char* kSkalakPlanar =
    R"({"ca": 0.45, "capsule": {"law": "skalak", "C": 1}, "flow": {"type": "planar-extension"}})";

// make_run (amp 0.9) with that control.
void make_skalak_planar_run(const fs::path& d) {
  make_run(d, 0.9, false);
  put(d / "control.json", kSkalakPlanar);
}

int run_capflow(const std::string& args, const fs::path& log) {
  const std::string cmd =
      std::string(CAPFLOW_EXE) + " figure " + args + " > " + log.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// Parses a .dat sidecar: blocks of numeric rows ('#' comments, blocks split by blank lines).
std::vector<std::vector<std::vector<double>>> read_dat(const fs::path& p) {
  std::vector<std::vector<std::vector<double>>> blocks;
  std::ifstream f(p);
  std::string line;
  bool in_block = false;
  while (std::getline(f, line)) {
    if (line.empty()) {
      in_block = false;
      continue;
    }
    if (line[0] == '#') continue;
    if (!in_block) blocks.emplace_back();
    in_block = true;
    std::istringstream in(line);
    std::vector<double> row;
    std::string tok;
    while (in >> tok) row.push_back(std::strtod(tok.c_str(), nullptr));
    blocks.back().push_back(row);
  }
  return blocks;
}

// Well-formed XML (expat), returns the root element name ("" when not well-formed).
std::string xml_root(const fs::path& p, std::string* error) {
  XML_Parser parser = XML_ParserCreate(nullptr);
  std::string root;
  XML_SetUserData(parser, &root);
  XML_SetStartElementHandler(parser, [](void* ud, const XML_Char* name, const XML_Char**) {
    auto* r = static_cast<std::string*>(ud);
    if (r->empty()) *r = name;
  });
  const std::string text = slurp(p);
  const bool ok =
      XML_Parse(parser, text.data(), static_cast<int>(text.size()), 1) != XML_STATUS_ERROR;
  if (!ok)
    *error = std::string(XML_ErrorString(XML_GetErrorCode(parser))) + " at line " +
             std::to_string(XML_GetCurrentLineNumber(parser));
  XML_ParserFree(parser);
  return ok ? root : "";
}

// Width and height from a PNG's IHDR chunk (0, 0 if not a PNG).
std::pair<int, int> png_size(const fs::path& p) {
  const std::string s = slurp(p);
  if (s.size() < 24 || s.compare(1, 3, "PNG") != 0) return {0, 0};
  auto be = [&](size_t o) {
    return (static_cast<unsigned char>(s[o]) << 24) | (static_cast<unsigned char>(s[o + 1]) << 16) |
           (static_cast<unsigned char>(s[o + 2]) << 8) | static_cast<unsigned char>(s[o + 3]);
  };
  return {static_cast<int>(be(16)), static_cast<int>(be(20))};
}

bool gnuplot_available() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

}  // namespace

TEST(FigureData, CsvAndNearest) {
  const fs::path d = fresh_dir("csv");
  put(d / "a.csv", "t,x,y\n0,1,2\n0.5,abc,3\n\n1,4,5\n2,6\n");  // last row incomplete
  const fig::Table t = fig::read_csv((d / "a.csv").string());
  ASSERT_EQ(t.rows(), 3);
  EXPECT_EQ(t.column("x")[0], 1);
  EXPECT_TRUE(std::isnan(t.column("x")[1]));
  EXPECT_EQ(t.column("y")[2], 5);
  EXPECT_THROW(t.column("z"), std::runtime_error);
  EXPECT_EQ(fig::nearest({0, 0.5, 1, 2}, 0.8), 2);
  EXPECT_EQ(fig::nearest({0, 0.5, 1, 2}, 0.75), 1);  // tie: the first
  EXPECT_EQ(fig::nearest({}, 1), -1);
}

TEST(FigureData, LoadSurfaceNearestInTimeFromOwnVtp) {
  const fs::path d = fresh_dir("surface");
  make_run(d / "a", 0.3, true);
  make_run(d / "b", 0.3, false);
  capflow::render::Snapshot s;
  std::string note;
  ASSERT_TRUE(app::load_surface((d / "a").string(), 0.8, &s, &note)) << note;
  EXPECT_EQ(s.time, 1.0);
  EXPECT_EQ(s.ne, 6);
  EXPECT_EQ(s.nb, 9);
  EXPECT_EQ(s.ca, 0.45);
  EXPECT_DOUBLE_EQ(s.diag.D, deformation(1, 0.3));
  std::string err;
  EXPECT_TRUE(s.IsValid(&err)) << err;
  // Positions are those written: the +x tip of the ellipsoid at t = 1 is 1 + D(1).
  double xmax = -1;
  for (int k = 0; k < s.num_nodes(); ++k) xmax = std::max(xmax, s.x[3 * k]);
  EXPECT_NEAR(xmax, 1 + deformation(1, 0.3), 1e-14);
  EXPECT_EQ(s.diag.tau_max, *std::max_element(s.tau1.begin(), s.tau1.end()));  // stored field
  ASSERT_TRUE(app::load_surface((d / "a").string(), 100, &s, &note));
  EXPECT_EQ(s.time, 2.0);
  // A damaged nearest file: the next nearest is used.
  put(d / "a" / app::surface_file_name(2), "<VTKFile");
  ASSERT_TRUE(app::load_surface((d / "a").string(), 100, &s, &note)) << note;
  EXPECT_EQ(s.time, 1.0);
  // No surface data: false, and the note says so.
  EXPECT_FALSE(app::load_surface((d / "b").string(), 1, &s, &note));
  EXPECT_NE(note.find("no surface data"), std::string::npos) << note;
  // Without surface.pvd the vtk/*.vtp files are scanned (time from their TimeValue).
  fs::remove(d / "a" / app::kSurfaceCollection);
  ASSERT_TRUE(app::load_surface((d / "a").string(), 0.1, &s, &note)) << note;
  EXPECT_EQ(s.time, 0.0);
}

TEST(FigureCommand, ShearRunsGetTheInclinationAndNoTipCurvature) {
  // A simple-shear run (its control.json says so) tank-treads: ts_inclination is drawn for it and
  // the +x tip's curvature is not; a straining run beside it keeps ts_edge_curvature.
  const fs::path d = fresh_dir("shear_kinds");
  make_run(d / "shear", 0.3, false);
  put(d / "shear" / "control.json", R"({"ca": 0.3, "flow": {"type": "simple-shear"}})");
  const fs::path out = d / "out";
  ASSERT_EQ(run_capflow(
                (d / "shear").string() + " -o " + out.string() + " --kinds timeseries --no-gnuplot",
                d / "log.txt"),
            0)
      << slurp(d / "log.txt");
  EXPECT_FALSE(fs::exists(out / "ts_edge_curvature.dat"));
  // the inclination from the first row with a long axis (D >= 1e-3): not at t = 0 (the sphere)
  const auto incl = read_dat(out / "ts_inclination.dat");
  ASSERT_EQ(incl.size(), 1u);
  const fig::Table ts = fig::read_csv((d / "shear" / "timeseries.csv").string());
  long first = 0;
  while (first < ts.rows() && ts.num(first, ts.col("D")) < 1e-3) ++first;
  ASSERT_GT(first, 0);
  ASSERT_EQ(static_cast<long>(incl[0].size()), ts.rows() - first);
  EXPECT_EQ(incl[0][0][0], ts.num(first, ts.col("t")));
  make_run(d / "planar", 0.3, false);
  const fs::path out2 = d / "out2";
  ASSERT_EQ(run_capflow((d / "shear").string() + " " + (d / "planar").string() + " -o " +
                            out2.string() + " --kinds timeseries --no-gnuplot",
                        d / "log2.txt"),
            0)
      << slurp(d / "log2.txt");
  EXPECT_TRUE(fs::exists(out2 / "ts_inclination.dat"));
  const std::string curv = slurp(out2 / "ts_edge_curvature.gp");
  EXPECT_NE(curv.find("'planar'"), std::string::npos) << curv;
  EXPECT_EQ(curv.find("'shear'"), std::string::npos) << curv;
  fs::remove_all(d);
}

TEST(FigureCommand, TankTreadingPhaseFollowsAMembranePoint) {
  // A rigid ellipsoid turning about y at -0.5 rad per unit time (as a rigid body in the shear
  // u = (z, 0, 0)), surfaces at t = 0, 0.5, .., 16 (-458 degrees in all: the phase crosses the
  // +-180 wrap twice): ts_tank_treading is the unwrapped angle of the point that starts highest
  // (the +z pole, 90 degrees), -0.5 rad per unit time exactly, and its last full turn took
  // T = 4 pi (f / G = 1 / (4 pi), 4 pi f / G = 1); a run without surfaces gets a note.
  const fs::path d = fresh_dir("tank_treading");
  make_run(d / "turning", 0.3, false);
  put(d / "turning" / "control.json", R"({"ca": 0.1, "flow": {"type": "simple-shear"}})");
  fs::create_directories(d / "turning" / "vtk");
  capflow::output::PvdCollection pvd((d / "turning" / app::kSurfaceCollection).string());
  const capflow::geometry::Mesh mesh(6, 7);
  const auto body = capflow::geometry::map_points(mesh.reference(),
                                                  capflow::geometry::ellipsoid_map(1.3, 0.9, 0.8));
  for (int k = 0; k <= 32; ++k) {
    const double t = 0.5 * k, a = -0.5 * t;
    Eigen::Matrix3d turn;
    turn << std::cos(a), 0, -std::sin(a), 0, 1, 0, std::sin(a), 0, std::cos(a);
    const Eigen::Matrix3Xd x = turn * body;
    capflow::render::Snapshot s;
    s.ne = 6;
    s.nb = 7;
    s.time = t;
    s.ca = 0.1;
    s.x.assign(x.data(), x.data() + x.size());
    s.tau1.assign(x.cols(), 0.0);
    s.tau2.assign(x.cols(), 0.0);
    const std::string f = app::surface_file_name(k);
    capflow::output::write_vtp((d / "turning" / f).string(), app::vtk_from_snapshot(s));
    pvd.add(t, f);
  }
  make_run(d / "bare", 0.3, false);
  put(d / "bare" / "control.json", R"({"ca": 0.1, "flow": {"type": "simple-shear"}})");
  const fs::path out = d / "out";
  ASSERT_EQ(run_capflow((d / "turning").string() + " " + (d / "bare").string() + " -o " +
                            out.string() + " --kinds timeseries --no-gnuplot",
                        d / "log.txt"),
            0)
      << slurp(d / "log.txt");
  const auto phase = read_dat(out / "ts_tank_treading.dat");
  ASSERT_EQ(phase.size(), 1u);
  ASSERT_EQ(phase[0].size(), 33u);
  for (const auto& row : phase[0])
    EXPECT_NEAR(row[1], 90 - 0.5 * row[0] * 180 / M_PI, 1e-9) << "t = " << row[0];
  const std::string manifest = slurp(out / "figures.md");
  EXPECT_NE(manifest.find("no surface.pvd"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("-28.6479 deg per unit G t"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("from t = 3.43363, took T G = 12.5664: f / G = 0.0795775, 4 pi f / G = 1"),
            std::string::npos)
      << manifest;
  fs::remove_all(d);
}

TEST(FigureCommand, SteadyDeformationWithTheSmallDeformationLine) {
  // steady_D_vs_ca: each run's (Ca, D) from steady.csv, and the small-deformation line of its law
  // and flow: Skalak C = 3 (Ks = 7) in planar extension D = (5/4)(3 + 1/7) Ca = 55/14 Ca,
  // neo-Hookean (Ks = 3) in simple shear 25/12 Ca
  const fs::path d = fresh_dir("steady_d");
  make_run(d / "sk", 0.3, false);
  put(d / "sk" / "control.json", R"({"ca": 0.3, "capsule": {"law": "skalak", "C": 3}})");
  make_run(d / "nh", 0.5, false);
  put(d / "nh" / "control.json",
      R"({"ca": 0.3, "capsule": {"law": "neo-hookean"}, "flow": {"type": "simple-shear"}})");
  const fs::path out = d / "out";
  ASSERT_EQ(run_capflow((d / "sk").string() + " " + (d / "nh").string() + " -o " + out.string() +
                            " --kinds steady --no-gnuplot",
                        d / "log.txt"),
            0)
      << slurp(d / "log.txt");
  const auto dat = read_dat(out / "steady_D_vs_ca.dat");
  ASSERT_EQ(dat.size(), 4u);  // two runs, two theory lines
  for (int r = 0; r < 2; ++r) {
    const fig::Table st = fig::read_csv((d / (r == 0 ? "sk" : "nh") / "steady.csv").string());
    ASSERT_EQ(static_cast<long>(dat[r].size()), st.rows());
    for (long i = 0; i < st.rows(); ++i) {
      EXPECT_EQ(dat[r][i][0], st.num(i, st.col("ca")));
      EXPECT_EQ(dat[r][i][1], st.num(i, st.col("D")));
    }
  }
  // the lines, in increasing slope: 25/12 (shear), 55/14 (planar extension), from 0 up to the
  // data's largest D (0.5 x 0.6) x 1.1
  const double slopes[2] = {25.0 / 12, 55.0 / 14};
  for (int k = 0; k < 2; ++k) {
    ASSERT_EQ(dat[2 + k].size(), 2u);
    EXPECT_EQ(dat[2 + k][0][0], 0.0);
    EXPECT_NEAR(dat[2 + k][1][1], 1.1 * 0.5 * 0.6, 1e-12);
    EXPECT_NEAR(dat[2 + k][1][1] / dat[2 + k][1][0], slopes[k], 1e-12);
  }
  EXPECT_NE(slurp(out / "steady_D_vs_ca.gp").find("small deformation"), std::string::npos);
  fs::remove_all(d);
}

TEST(FigureCommand, PublishedSteadyStatesAndTheoryAreDrawnWhereTheyApply) {
  // A Skalak C = 1 run in planar extension: the paper quotes steady states at Ca = 0.45 and 0.6
  // (its own and Lac et al. 2004's), which fall inside the run's Ca range [0.15, 0.6]; its ts_D
  // ends at Ca = 0.45, so the paper's steady D = 0.548 is drawn across it. --no-references
  // leaves all of them out.
  const fs::path d = fresh_dir("refs");
  make_skalak_planar_run(d / "sk");
  const fs::path out = d / "out", bare = d / "bare";
  ASSERT_EQ(run_capflow((d / "sk").string() + " -o " + out.string() +
                            " --kinds timeseries,steady --no-gnuplot",
                        d / "log.txt"),
            0)
      << slurp(d / "log.txt");
  const auto D = read_dat(out / "steady_D_vs_ca.dat");
  ASSERT_EQ(D.size(), 4u);  // the run, the small-deformation line, two published sources
  const std::vector<std::vector<double>> paper = {{0.45, 0.548}, {0.6, 0.595}},
                                         lac = {{0.45, 0.549}, {0.6, 0.6}};
  EXPECT_EQ(D[2], paper);
  EXPECT_EQ(D[3], lac);
  EXPECT_NEAR(D[1][1][1] / D[1][1][0], 1.25 * (3 + 1.0 / 3), 1e-12);  // Ks = 1 + 2C = 3
  const auto L = read_dat(out / "steady_half_lengths_vs_ca.dat");
  ASSERT_EQ(L.size(), 3u);
  EXPECT_EQ(L[1], (std::vector<std::vector<double>>{{0.45, 1.76}, {0.6, 1.90}}));
  EXPECT_EQ(L[2], (std::vector<std::vector<double>>{{0.45, 1.78}, {0.6, 1.95}}));
  const auto ts = read_dat(out / "ts_D.dat");
  ASSERT_EQ(ts.size(), 2u);
  EXPECT_EQ(ts[1], (std::vector<std::vector<double>>{{0, 0.548}, {2, 0.548}}));
  // a run whose timeseries.csv has no ca column (older runs): no paper line on its ts_D
  {
    std::istringstream in(slurp(d / "sk" / "timeseries.csv"));
    std::ostringstream without_ca;
    for (std::string line; std::getline(in, line);) {
      const size_t a = line.find(','), b = line.find(',', a + 1);
      without_ca << line.substr(0, a) << line.substr(b) << "\n";  // drops the second column
    }
    put(d / "old" / "timeseries.csv", without_ca.str());
    put(d / "old" / "control.json", kSkalakPlanar);
    ASSERT_EQ(run_capflow((d / "old").string() + " -o " + (d / "out_old").string() +
                              " --kinds timeseries --no-gnuplot",
                          d / "log_old.txt"),
              0)
        << slurp(d / "log_old.txt");
    EXPECT_EQ(read_dat(d / "out_old" / "ts_D.dat").size(), 1u);
  }
  const std::string gp = slurp(out / "steady_D_vs_ca.gp");
  EXPECT_NE(gp.find("'Dodson \\& Dimitrakopoulos (SBE)'"), std::string::npos)
      << gp;  // \\& prints & in enhanced text

  ASSERT_EQ(run_capflow((d / "sk").string() + " -o " + bare.string() +
                            " --kinds timeseries,steady --no-gnuplot --no-references",
                        d / "log2.txt"),
            0)
      << slurp(d / "log2.txt");
  EXPECT_EQ(read_dat(bare / "steady_D_vs_ca.dat").size(), 1u);
  EXPECT_EQ(read_dat(bare / "steady_half_lengths_vs_ca.dat").size(), 1u);
  EXPECT_EQ(read_dat(bare / "ts_D.dat").size(), 1u);
  fs::remove_all(d);
}

TEST(FigureCommand, NoFigureOfReferencesAlone) {
  // A Skalak C = 1 run that reached no steady state: steady_D_vs_ca would hold the theory line
  // and the published values only, so it is skipped with a note.
  const fs::path d = fresh_dir("refs_alone");
  make_skalak_planar_run(d / "sk");
  put(d / "sk" / "steady.csv", "ca,L,S,W,Lc,Sc,Wc,D,area,edge_curvature,tau_max,tau_min\n");
  const fs::path out = d / "out";
  ASSERT_EQ(run_capflow((d / "sk").string() + " -o " + out.string() +
                            " --kinds timeseries,steady --no-gnuplot",
                        d / "log.txt"),
            0)
      << slurp(d / "log.txt");
  EXPECT_FALSE(fs::exists(out / "steady_D_vs_ca.dat"));
  EXPECT_NE(slurp(out / "figures.md").find("steady_D_vs_ca: skipped, no data in any run"),
            std::string::npos);
  EXPECT_TRUE(fs::exists(out / "ts_D.dat"));
  fs::remove_all(d);
}

TEST(FigureCommand, AxesCarryUnitsAndTheCaptionStaysOutOfThePlot) {
  // Every script labels both axes, draws no title (the caption is in figures.md), leaves a margin
  // around the data; ts_D_ca stacks D(t) over Ca(t) with the run's Ca in its second block.
  const fs::path d = fresh_dir("typo");
  make_run(d / "a", 0.3, false);
  const fs::path out = d / "out";
  ASSERT_EQ(run_capflow((d / "a").string() + " -o " + out.string() +
                            " --kinds timeseries,steady,profiles --no-gnuplot",
                        d / "log.txt"),
            0)
      << slurp(d / "log.txt");
  const std::string manifest = slurp(out / "figures.md");
  int scripts = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    if (e.path().extension() != ".gp") continue;
    ++scripts;
    const std::string gp = slurp(e.path()), name = e.path().stem().string();
    SCOPED_TRACE(name);
    EXPECT_EQ(gp.find("set title"), std::string::npos);
    EXPECT_NE(gp.find("set xlabel '"), std::string::npos);
    EXPECT_NE(gp.find("set ylabel '"), std::string::npos);
    EXPECT_NE(gp.find("set offsets graph"), std::string::npos);
    EXPECT_NE(gp.find("set minussign"), std::string::npos);
    EXPECT_NE(manifest.find("**" + name + "**: "), std::string::npos);
  }
  EXPECT_GT(scripts, 15);
  EXPECT_NE(slurp(out / "ts_D.gp").find("set xlabel '{/:Italic t} / {/:Italic G}^{−1}'"),
            std::string::npos);
  EXPECT_NE(slurp(out / "ts_tension.gp").find("_{max}"), std::string::npos);
  EXPECT_NE(slurp(out / "profiles_a_z.gp").find("set size ratio -1"), std::string::npos);
  // L, S, W: one colour each
  const std::string lsw = slurp(out / "ts_LSW.gp");
  for (const char* c : {"#0072b2", "#d55e00", "#009e73"}) EXPECT_NE(lsw.find(c), std::string::npos);
  const std::string dc = slurp(out / "ts_D_ca.gp");
  EXPECT_NE(dc.find("set multiplot layout 2,1"), std::string::npos) << dc;
  const auto dat = read_dat(out / "ts_D_ca.dat");
  ASSERT_EQ(dat.size(), 2u);
  const fig::Table ts = fig::read_csv((d / "a" / "timeseries.csv").string());
  ASSERT_EQ(static_cast<long>(dat[1].size()), ts.rows());
  for (long r = 0; r < ts.rows(); ++r) EXPECT_EQ(dat[1][r][1], ts.num(r, ts.col("ca")));
  fs::remove_all(d);
}

TEST(FigureCommand, EveryKindFromTwoRunsWithMatchingSidecars) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed (apt-get install gnuplot-nox)";
  const fs::path d = fresh_dir("all");
  make_run(d / "skalak", 0.3, true);
  make_run(d / "neo", 0.5, false);
  const fs::path out = d / "out";
  const int rc = run_capflow((d / "skalak").string() + " " + (d / "neo").string() + " -o " +
                                 out.string() + " --times 0,1,2 --width 320 --height 240",
                             d / "log.txt");
  ASSERT_EQ(rc, 0) << slurp(d / "log.txt");
  const std::vector<std::string> plots = {"ts_D",
                                          "ts_LSW",
                                          "ts_edge_curvature",
                                          "ts_tension",
                                          "ts_D_ca",
                                          "ts_volume_drift",
                                          "profiles_skalak_z",
                                          "profiles_skalak_y",
                                          "profiles_neo_z",
                                          "profiles_neo_y",
                                          "profiles_compare_z",
                                          "profiles_compare_y",
                                          "steady_half_lengths_vs_ca",
                                          "steady_ScWc_vs_Lc",
                                          "steady_ScWc_ratio_vs_Lc",
                                          "steady_area_vs_ca",
                                          "steady_area_vs_Lc",
                                          "steady_edge_curvature_vs_Lc",
                                          "steady_tau_max_vs_ca",
                                          "steady_tau_max_vs_Lc",
                                          "steady_tau_max_vs_strain",
                                          "steady_D_vs_ca"};
  const std::string manifest = slurp(out / "figures.md");
  for (const auto& p : plots) {
    SCOPED_TRACE(p);
    for (const char* ext : {".gp", ".dat", ".svg", ".png"}) {
      ASSERT_TRUE(fs::exists(out / (p + ext))) << ext << "\n" << slurp(d / "log.txt");
      EXPECT_GT(fs::file_size(out / (p + ext)), 100u) << ext;
    }
    std::string err;
    EXPECT_EQ(xml_root(out / (p + ".svg"), &err), "svg") << err;
    EXPECT_GT(png_size(out / (p + ".png")).first, 0);
    EXPECT_NE(manifest.find("**" + p + "**"), std::string::npos);
    EXPECT_FALSE(fs::exists(out / (p + ".gnuplot.log")));
  }

  // Time series sidecar: block r holds run r's (t, D) exactly.
  for (const auto& [block, run] : {std::pair<int, const char*>{0, "skalak"}, {1, "neo"}}) {
    const fig::Table ts = fig::read_csv((d / run / "timeseries.csv").string());
    const auto dat = read_dat(out / "ts_D.dat");
    ASSERT_EQ(dat.size(), 2u);
    ASSERT_EQ(static_cast<long>(dat[block].size()), ts.rows());
    const auto t = ts.column("t"), D = ts.column("D");
    for (long r = 0; r < ts.rows(); ++r) {
      EXPECT_EQ(dat[block][r][0], t[r]);
      EXPECT_EQ(dat[block][r][1], D[r]);
    }
    const auto lsw = read_dat(out / "ts_tension.dat");
    const auto tmax = ts.column("tau_max"), tmin = ts.column("tau_min");
    for (long r = 0; r < ts.rows(); ++r) {
      EXPECT_EQ(lsw[block][r][1], tmax[r]);
      EXPECT_EQ(lsw[block][r][2], tmin[r]);
    }
  }
  // Steady sidecars: Sc/Wc vs Lc and (Lc^2-1)/2 computed from steady.csv; log plot has
  // every (positive) curvature.
  {
    const fig::Table st = fig::read_csv((d / "neo" / "steady.csv").string());
    const auto lc = st.column("Lc"), sc = st.column("Sc"), wc = st.column("Wc");
    const auto ratio = read_dat(out / "steady_ScWc_ratio_vs_Lc.dat");
    ASSERT_EQ(ratio.size(), 2u);
    ASSERT_EQ(static_cast<long>(ratio[1].size()), st.rows());
    for (long r = 0; r < st.rows(); ++r) {
      EXPECT_EQ(ratio[1][r][0], lc[r]);
      EXPECT_EQ(ratio[1][r][1], sc[r] / wc[r]);
    }
    const auto strain = read_dat(out / "steady_tau_max_vs_strain.dat");
    const auto tmax = st.column("tau_max");
    for (long r = 0; r < st.rows(); ++r) {
      EXPECT_EQ(strain[1][r][0], (lc[r] * lc[r] - 1) / 2);
      EXPECT_EQ(strain[1][r][1], tmax[r]);
    }
    const auto half = read_dat(out / "steady_half_lengths_vs_ca.dat");
    const auto ca = st.column("ca"), L = st.column("L"), Lcc = st.column("Lc");
    for (long r = 0; r < st.rows(); ++r) {
      EXPECT_EQ(half[1][r][0], ca[r]);
      EXPECT_EQ(half[1][r][1], L[r]);
      EXPECT_EQ(half[1][r][4], Lcc[r]);
    }
    EXPECT_NE(slurp(out / "steady_edge_curvature_vs_Lc.gp").find("set logscale y"),
              std::string::npos);
  }
  // Profiles: block 0 the unit circle; blocks 1.. the profiles at t = 0, 1, 2 (the files with
  // index 0, 2, 4), points in file order, first point repeated at the end.
  {
    const auto dat = read_dat(out / "profiles_skalak_y.dat");
    ASSERT_EQ(dat.size(), 4u);
    for (const auto& r : dat[0]) EXPECT_NEAR(std::hypot(r[0], r[1]), 1.0, 1e-14);
    for (int k = 0; k < 3; ++k) {
      char name[64];
      std::snprintf(name, sizeof name, "profiles/profile_%06d.csv", 2 * k);
      const fig::Profile p = fig::read_profile((d / "skalak" / name).string());
      EXPECT_EQ(p.t, 1.0 * k);
      ASSERT_EQ(dat[k + 1].size(), p.y.size() + 1);
      for (size_t i = 0; i < p.y.size(); ++i) {
        EXPECT_EQ(dat[k + 1][i][0], p.y[i].first);
        EXPECT_EQ(dat[k + 1][i][1], p.y[i].second);
      }
      EXPECT_EQ(dat[k + 1].back(), dat[k + 1].front());
    }
    // Comparison: circle + one block per run, each at the last requested time (t = 2).
    const auto cmp = read_dat(out / "profiles_compare_z.dat");
    ASSERT_EQ(cmp.size(), 3u);
    const fig::Profile neo = fig::read_profile((d / "neo/profiles/profile_000004.csv").string());
    EXPECT_EQ(cmp[2][0][0], neo.z[0].first);
    EXPECT_NEAR(cmp[2][0][0], 1 + deformation(2, 0.5), 1e-9);
  }
  // 3-D views: skalak has surfaces -> rendered at 320 x 240; neo has none -> the nearest frame
  // (64 x 48) is copied, and the manifest says it was not rendered.
  for (const char* t : {"t0", "t1", "t2"}) {
    const fs::path v = out / (std::string("view_skalak_") + t + ".png");
    ASSERT_TRUE(fs::exists(v)) << slurp(d / "log.txt");
    EXPECT_EQ(png_size(v), std::make_pair(320, 240)) << slurp(d / "log.txt");
  }
  EXPECT_EQ(slurp(out / "view_neo_t1.png"), slurp(d / "neo/frames/frame_000002.png"));
  EXPECT_EQ(slurp(out / "view_neo_t2.png"), slurp(d / "neo/frames/frame_000004.png"));
  EXPECT_NE(manifest.find("view_neo_t1: NOT rendered"), std::string::npos) << manifest;
  EXPECT_NE(slurp(d / "log.txt").find("NOT rendered"), std::string::npos);
}

TEST(FigureCommand, RenderedViewsFollowTheSurfaceInTime) {
  // The rendered view changes with the requested time (the capsule elongates), and a time
  // between saved surfaces gets the nearest one, named by the time drawn (one file for both).
  const fs::path d = fresh_dir("views");
  make_run(d / "a", 0.4, true);
  const int rc = run_capflow((d / "a").string() + " -o " + (d / "out").string() +
                                 " --kinds views --times 0,2,1.9 --width 160 --height 120",
                             d / "log.txt");
  ASSERT_EQ(rc, 0) << slurp(d / "log.txt");
  const std::string v0 = slurp(d / "out/view_a_t0.png"), v2 = slurp(d / "out/view_a_t2.png");
  ASSERT_FALSE(v0.empty());
  EXPECT_NE(v0, v2);
  EXPECT_FALSE(fs::exists(d / "out/view_a_t1.9.png"));
  EXPECT_NE(slurp(d / "out/figures.md").find("requested t = 1.9, nearest saved state t = 2"),
            std::string::npos);
  // without --times: the final state (the newest checkpoint; this run has none: its last
  // surface), named by its time, from the view asked for
  ASSERT_EQ(run_capflow((d / "a").string() + " -o " + (d / "out2").string() +
                            " --kinds views --view xy --width 160 --height 120",
                        d / "log2.txt"),
            0)
      << slurp(d / "log2.txt");
  EXPECT_NE(slurp(d / "out2/figures.md").find("(xy view)"), std::string::npos);
  EXPECT_TRUE(fs::exists(d / "out2/view_a_t2.png"));
}

TEST(FigureCommand, MissingDataIsSkippedWithAMessage) {
  const fs::path d = fresh_dir("missing");
  make_run(d / "full", 0.3, false);
  fs::create_directories(d / "bare");
  fs::copy_file(d / "full/timeseries.csv", d / "bare/timeseries.csv");
  const int rc = run_capflow((d / "bare").string() + " -o " + (d / "out").string() +
                                 " --kinds timeseries,steady,profiles --no-gnuplot",
                             d / "log.txt");
  ASSERT_EQ(rc, 0) << slurp(d / "log.txt");
  const std::string log = slurp(d / "log.txt");
  EXPECT_NE(log.find("run bare: no steady.csv"), std::string::npos) << log;
  EXPECT_NE(log.find("run bare: no profiles"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(d / "out/ts_D.gp"));
  EXPECT_TRUE(fs::exists(d / "out/ts_D.dat"));
  EXPECT_FALSE(fs::exists(d / "out/ts_D.svg"));  // --no-gnuplot: scripts only
  EXPECT_FALSE(fs::exists(d / "out/steady_area_vs_Lc.dat"));
  // The kept script reproduces the figure by itself (what users do after restyling).
  if (gnuplot_available()) {
    const std::string c = "cd " + (d / "out").string() + " && gnuplot ts_D.gp";
    ASSERT_EQ(std::system(c.c_str()), 0);
    std::string err;
    EXPECT_EQ(xml_root(d / "out/ts_D.svg", &err), "svg") << err;
  }
  // User errors: exit code 2 and a message.
  EXPECT_EQ(run_capflow((d / "nope").string() + " -o " + (d / "out2").string(), d / "log2.txt"), 2);
  EXPECT_NE(slurp(d / "log2.txt").find("not a run directory"), std::string::npos);
  EXPECT_EQ(run_capflow((d / "full").string() + " --kinds bogus -o " + (d / "out3").string(),
                        d / "log3.txt"),
            2);
}
