// ParaView export (output/vtk.h): our own reader round-trips both encodings bit for bit, and
// VTK's own XML reader (Debian's python3-vtk9, run through /usr/bin/python3) reads the files
// with the right point/cell counts, arrays and time values; the quads close a sphere (area
// -> 4 pi) and face outwards (VTK's own normals agree with ours). The .pvd collection is valid
// after every add and parses with Python's XML parser; every file it lists loads in VTK with
// its time value.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "output/vtk.h"

namespace fs = std::filesystem;
using capflow::output::PvdCollection;
using capflow::output::VtkArray;
using capflow::output::VtkEncoding;
using capflow::output::VtkSurface;

namespace {

const double kPi = 3.14159265358979323846;

fs::path fresh_dir(const std::string& name) {
  const auto d =
      fs::temp_directory_path() / ("capflow_vtk_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A unit sphere on a cube-sphere grid: 6 faces, n x n points each, equiangular parameters,
// point k = (e*n + j)*n + i, (i, j) ordered so that (d/di x) x (d/dj x) points outwards.
// Arrays: tau1 = 1 + x, tau2 = z^2, Normals = x (exact outward normal), velocity = (-y, x, 0).
VtkSurface sphere(int n, double time) {
  VtkSurface s;
  s.ne = 6;
  s.n = n;
  s.time = time;
  const long np = s.num_points();
  s.x.resize(3 * np);
  VtkArray tau1{1, std::vector<double>(np)}, tau2{1, std::vector<double>(np)};
  VtkArray normals{3, std::vector<double>(3 * np)}, vel{3, std::vector<double>(3 * np)};
  // Face e: axis a = e/2, sign sg; in-face axes (b, c) chosen so (e_b x e_c) = sg e_a.
  for (int e = 0; e < 6; ++e) {
    const int a = e / 2;
    const double sg = e % 2 ? -1.0 : 1.0;
    int b = (a + 1) % 3, c = (a + 2) % 3;
    if (sg < 0) std::swap(b, c);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double u = std::tan(kPi / 4 * (-1 + 2.0 * i / (n - 1)));
        const double v = std::tan(kPi / 4 * (-1 + 2.0 * j / (n - 1)));
        double p[3];
        p[a] = sg;
        p[b] = u;
        p[c] = v;
        const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        const long k = (static_cast<long>(e) * n + j) * n + i;
        for (int d = 0; d < 3; ++d) {
          s.x[3 * k + d] = p[d] / r;
          normals.values[3 * k + d] = p[d] / r;
        }
        tau1.values[k] = 1 + s.x[3 * k];
        tau2.values[k] = s.x[3 * k + 2] * s.x[3 * k + 2];
        vel.values[3 * k] = -s.x[3 * k + 1];
        vel.values[3 * k + 1] = s.x[3 * k];
        vel.values[3 * k + 2] = 0;
      }
  }
  s.point_arrays["tau1"] = tau1;
  s.point_arrays["tau2"] = tau2;
  s.point_arrays["Normals"] = normals;
  s.point_arrays["velocity"] = vel;
  s.field_scalars["ca"] = 0.45;
  s.field_scalars["D"] = 0.125;
  return s;
}

const char* kPython = "/usr/bin/python3";

bool python_vtk_available(std::string* why) {
  if (!fs::exists(kPython)) {
    *why = std::string(kPython) + " not found";
    return false;
  }
  const std::string cmd = std::string(kPython) + " -c 'import vtkmodules.vtkIOXML' >/dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    *why = "python3-vtk9 is not installed (apt-get install python3-vtk9; scripts/setup does)";
    return false;
  }
  return true;
}

// Runs a Python script; returns its stdout parsed as "key value" lines.
std::map<std::string, std::string> run_python(const fs::path& dir, const std::string& script) {
  const fs::path py = dir / "check.py", out = dir / "check.out";
  std::ofstream(py) << script;
  const std::string cmd = std::string(kPython) + " " + py.string() + " > " + out.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream f(out);
  std::stringstream all;
  all << f.rdbuf();
  EXPECT_EQ(rc, 0) << "python failed:\n" << all.str();
  std::map<std::string, std::string> kv;
  std::istringstream lines(all.str());
  std::string line;
  while (std::getline(lines, line)) {
    const auto sp = line.find(' ');
    if (sp != std::string::npos) kv[line.substr(0, sp)] = line.substr(sp + 1);
  }
  return kv;
}

}  // namespace

TEST(Base64, KnownVectorsAndRoundTrip) {
  using capflow::output::base64_decode;
  using capflow::output::base64_encode;
  EXPECT_EQ(base64_encode("Man", 3), "TWFu");
  EXPECT_EQ(base64_encode("Ma", 2), "TWE=");
  EXPECT_EQ(base64_encode("M", 1), "TQ==");
  EXPECT_EQ(base64_encode("", 0), "");
  std::string all(256, '\0');
  for (int i = 0; i < 256; ++i) all[i] = static_cast<char>(i);
  for (size_t len : {0u, 1u, 2u, 3u, 4u, 5u, 255u, 256u}) {
    const auto dec = base64_decode(base64_encode(all.data(), len));
    ASSERT_EQ(dec.size(), len);
    for (size_t k = 0; k < len; ++k) EXPECT_EQ(dec[k], static_cast<unsigned char>(all[k]));
  }
  EXPECT_THROW(base64_decode("TW*u"), std::runtime_error);
}

// Copies of each grid point (the points within 1e-12 of it, itself included), by brute force.
std::vector<int> multiplicity(const VtkSurface& s) {
  const long np = s.num_points();
  std::vector<int> m(static_cast<size_t>(np), 0);
  for (long a = 0; a < np; ++a)
    for (long b = 0; b < np; ++b) {
      double d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(s.x[3 * a + c] - s.x[3 * b + c]));
      if (d < 1e-12) ++m[static_cast<size_t>(a)];
    }
  return m;
}

TEST(Vtk, OwnReaderRoundTripsBothEncodings) {
  const fs::path d = fresh_dir("roundtrip");
  const VtkSurface s = sphere(7, 1.0 / 3.0);
  const std::vector<int> copies = multiplicity(s);
  for (VtkEncoding enc : {VtkEncoding::Ascii, VtkEncoding::Base64}) {
    const fs::path p = d / (enc == VtkEncoding::Ascii ? "a.vtp" : "b.vtp");
    capflow::output::write_vtp(p.string(), s, enc);
    EXPECT_FALSE(fs::exists(p.string() + ".tmp"));
    const VtkSurface r = capflow::output::read_vtp(p.string());
    EXPECT_EQ(r.ne, 6);
    EXPECT_EQ(r.n, 7);
    EXPECT_EQ(r.time, s.time);  // bit for bit (%.17g or raw bytes)
    // Bit for bit at the points of one element; at the welded edge points (copies equal to
    // rounding here) the mean of the copies
    const auto expect_back = [&](const std::vector<double>& got, const std::vector<double>& want,
                                 int comps, const std::string& name) {
      ASSERT_EQ(got.size(), want.size()) << name;
      for (size_t k = 0; k < copies.size(); ++k)
        for (int c = 0; c < comps; ++c) {
          const size_t i = k * comps + c;
          if (copies[k] == 1)
            EXPECT_EQ(got[i], want[i]) << name << " point " << k;
          else
            EXPECT_NEAR(got[i], want[i], 1e-15) << name << " point " << k;
        }
    };
    expect_back(r.x, s.x, 3, "x");
    ASSERT_EQ(r.point_arrays.size(), s.point_arrays.size());
    for (const auto& [name, a] : s.point_arrays) {
      ASSERT_TRUE(r.point_arrays.count(name)) << name;
      EXPECT_EQ(r.point_arrays.at(name).components, a.components) << name;
      expect_back(r.point_arrays.at(name).values, a.values, a.components, name);
    }
    EXPECT_EQ(r.field_scalars, s.field_scalars);
  }
}

TEST(Vtk, ElementEdgesAreWrittenOnce) {
  // n x n points on each of the 6 faces: 6 (n-2)^2 interior, 12 (n-2) on edges, 8 corners
  const fs::path d = fresh_dir("weld");
  for (int n : {2, 3, 7, 12}) {
    const VtkSurface s = sphere(n, 0);
    capflow::output::write_vtp((d / "w.vtp").string(), s, VtkEncoding::Ascii);
    std::ifstream f(d / "w.vtp");
    std::stringstream all;
    all << f.rdbuf();
    const std::string text = all.str();
    const long unique = 6L * (n - 2) * (n - 2) + 12L * (n - 2) + 8;
    EXPECT_NE(text.find("NumberOfPoints=\"" + std::to_string(unique) + "\""), std::string::npos)
        << "n " << n;
    // the same count from the copies found by brute force: sum over grid points of 1/copies
    double sum = 0;
    for (int c : multiplicity(s)) sum += 1.0 / c;
    EXPECT_NEAR(sum, static_cast<double>(unique), 1e-9) << "n " << n;
    EXPECT_EQ(capflow::output::read_vtp((d / "w.vtp").string()).num_points(), s.num_points());
  }
}

TEST(Vtk, InvalidSurfacesAreRefusedWithAMessage) {
  const fs::path d = fresh_dir("invalid");
  VtkSurface s = sphere(3, 0);
  s.point_arrays["tau1"].values.pop_back();
  try {
    capflow::output::write_vtp((d / "x.vtp").string(), s);
    FAIL() << "expected a throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("tau1"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(d / "x.vtp"));
  VtkSurface t = sphere(3, 0);
  t.x.resize(5);
  EXPECT_THROW(capflow::output::write_vtp((d / "y.vtp").string(), t), std::runtime_error);
  VtkSurface u = sphere(3, 0);
  u.field_scalars["TimeValue"] = 1;
  EXPECT_THROW(capflow::output::write_vtp((d / "z.vtp").string(), u), std::runtime_error);
  std::ofstream(d / "junk.vtp") << "<?xml version=\"1.0\"?><VTKFile type=\"ImageData\"></VTKFile>";
  EXPECT_THROW(capflow::output::read_vtp((d / "junk.vtp").string()), std::runtime_error);
  EXPECT_THROW(capflow::output::read_vtp((d / "missing.vtp").string()), std::runtime_error);
}

TEST(Vtk, VtkXmlReaderReadsCountsArraysTimeAndGeometry) {
  std::string why;
  if (!python_vtk_available(&why)) GTEST_SKIP() << "VTK reader check skipped: " << why;
  const fs::path d = fresh_dir("vtkreader");
  const int n = 13;
  const VtkSurface s = sphere(n, 2.5);
  const std::vector<int> copies = multiplicity(s);
  capflow::output::write_vtp((d / "ascii.vtp").string(), s, VtkEncoding::Ascii);
  capflow::output::write_vtp((d / "binary.vtp").string(), s, VtkEncoding::Base64);
  for (const char* file : {"ascii.vtp", "binary.vtp"}) {
    SCOPED_TRACE(file);
    const std::string script = std::string(R"(
import sys
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.vtkFiltersCore import vtkTriangleFilter, vtkPolyDataNormals
from vtkmodules.vtkFiltersCore import vtkMassProperties
r = vtkXMLPolyDataReader()
r.SetFileName(sys.argv[0].replace('check.py', ')") +
                               file + R"('))
r.Update()
if r.GetErrorCode() != 0:
    print('error', r.GetErrorCode()); sys.exit(1)
pd = r.GetOutput()
print('points', pd.GetNumberOfPoints())
print('cells', pd.GetNumberOfCells())
print('polys', pd.GetNumberOfPolys())
sizes = set(pd.GetCell(c).GetNumberOfPoints() for c in range(pd.GetNumberOfCells()))
print('cellsizes', ','.join(str(x) for x in sorted(sizes)))
ptd = pd.GetPointData()
for i in range(ptd.GetNumberOfArrays()):
    a = ptd.GetArray(i)
    s = 0.0
    for t in range(a.GetNumberOfTuples()):
        for c in range(a.GetNumberOfComponents()):
            s += a.GetComponent(t, c)
    print('array_' + a.GetName(), a.GetNumberOfComponents(), a.GetNumberOfTuples(), repr(s))
el = pd.GetCellData().GetArray('element')
print('element', el.GetNumberOfTuples() if el else 0, repr(el.GetRange()[0]) if el else '-', repr(el.GetRange()[1]) if el else '-')
print('active_scalars', ptd.GetScalars().GetName() if ptd.GetScalars() else 'none')
print('active_normals', ptd.GetNormals().GetName() if ptd.GetNormals() else 'none')
fd = pd.GetFieldData()
for name in ('TimeValue', 'ne', 'n', 'ca', 'D'):
    a = fd.GetArray(name)
    print('field_' + name, repr(a.GetValue(0)) if a else 'missing')
tri = vtkTriangleFilter(); tri.SetInputData(pd); tri.Update()
mp = vtkMassProperties(); mp.SetInputData(tri.GetOutput()); mp.Update()
print('area', repr(mp.GetSurfaceArea()))
# VTK's own cell normals from the geometry vs the outward direction (the centroid).
nf = vtkPolyDataNormals(); nf.SetInputData(pd); nf.ComputeCellNormalsOn()
nf.ComputePointNormalsOff(); nf.AutoOrientNormalsOff(); nf.ConsistencyOff(); nf.SplittingOff()
nf.Update()
out = nf.GetOutput(); cn = out.GetCellData().GetNormals()
worst = 2.0
for c in range(out.GetNumberOfCells()):
    ids = out.GetCell(c).GetPointIds()
    cx = [sum(out.GetPoint(ids.GetId(k))[d] for k in range(4)) / 4 for d in range(3)]
    r = sum(x * x for x in cx) ** 0.5
    worst = min(worst, sum(cn.GetTuple3(c)[d] * cx[d] / r for d in range(3)))
print('min_outward_cos', repr(worst))
)";
    const auto kv = run_python(d, script);
    ASSERT_FALSE(kv.empty());
    const long unique = 6L * (n - 2) * (n - 2) + 12L * (n - 2) + 8;  // the edges welded
    EXPECT_EQ(kv.at("points"), std::to_string(unique));
    EXPECT_EQ(kv.at("cells"), std::to_string(6 * (n - 1) * (n - 1)));
    EXPECT_EQ(kv.at("polys"), std::to_string(6 * (n - 1) * (n - 1)));
    EXPECT_EQ(kv.at("cellsizes"), "4");
    for (const auto& [name, a] : s.point_arrays) {
      ASSERT_TRUE(kv.count("array_" + name)) << name;
      std::istringstream in(kv.at("array_" + name));
      int comps = 0;
      long tuples = 0;
      double sum = 0;
      in >> comps >> tuples >> sum;
      EXPECT_EQ(comps, a.components) << name;
      EXPECT_EQ(tuples, unique) << name;
      // each welded point once: the grid points' values weighted by 1 / their copies
      double want = 0;
      for (long k = 0; k < s.num_points(); ++k)
        for (int c = 0; c < a.components; ++c)
          want +=
              a.values[static_cast<size_t>(k * a.components + c)] / copies[static_cast<size_t>(k)];
      EXPECT_NEAR(sum, want, 1e-9 * (1 + std::abs(want))) << name;
    }
    EXPECT_EQ(kv.at("element"), std::to_string(6 * (n - 1) * (n - 1)) + " 0.0 5.0");
    EXPECT_EQ(kv.at("active_scalars"), "tau1");
    EXPECT_EQ(kv.at("active_normals"), "Normals");
    EXPECT_EQ(std::stod(kv.at("field_TimeValue")), 2.5);
    EXPECT_EQ(std::stod(kv.at("field_ne")), 6);
    EXPECT_EQ(std::stod(kv.at("field_n")), n);
    EXPECT_EQ(std::stod(kv.at("field_ca")), 0.45);
    EXPECT_EQ(std::stod(kv.at("field_D")), 0.125);
    // Flat quads inscribed in the unit sphere: area below 4 pi by O(h^2), h ~ pi/(2(n-1)).
    const double area = std::stod(kv.at("area"));
    EXPECT_LT(area, 4 * kPi);
    EXPECT_GT(area, 4 * kPi * (1 - 0.02));
    EXPECT_GT(std::stod(kv.at("min_outward_cos")), 0.95);  // every quad faces outwards
  }
}

TEST(Vtk, AreaConvergesQuadraticallyInVtk) {
  // The quads are a faithful surface: VTK's area of the quads converges to 4 pi at order 2.
  std::string why;
  if (!python_vtk_available(&why)) GTEST_SKIP() << "VTK reader check skipped: " << why;
  const fs::path d = fresh_dir("area");
  std::string files;
  for (int n : {9, 17, 33}) {
    const std::string f = "s" + std::to_string(n) + ".vtp";
    capflow::output::write_vtp((d / f).string(), sphere(n, 0));
    files += "'" + (d / f).string() + "',";
  }
  const auto kv = run_python(d, R"(
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.vtkFiltersCore import vtkTriangleFilter, vtkMassProperties
for i, f in enumerate([)" + files + R"(]):
    r = vtkXMLPolyDataReader(); r.SetFileName(f); r.Update()
    t = vtkTriangleFilter(); t.SetInputData(r.GetOutput()); t.Update()
    m = vtkMassProperties(); m.SetInputData(t.GetOutput()); m.Update()
    print('area%d' % i, repr(m.GetSurfaceArea()))
)");
  const double e0 = 4 * kPi - std::stod(kv.at("area0"));
  const double e1 = 4 * kPi - std::stod(kv.at("area1"));
  const double e2 = 4 * kPi - std::stod(kv.at("area2"));
  const double p1 = std::log2(e0 / e1), p2 = std::log2(e1 / e2);
  EXPECT_GT(p1, 1.8) << e0 << " " << e1;
  EXPECT_GT(p2, 1.9) << e1 << " " << e2;
  EXPECT_LT(p2, 2.2);
}

TEST(Vtk, ReadsFilesWrittenByVtkItself) {
  // Our reader against VTK's writer (inline ascii and uncompressed binary, both header types).
  std::string why;
  if (!python_vtk_available(&why)) GTEST_SKIP() << "VTK writer check skipped: " << why;
  const fs::path d = fresh_dir("vtkwriter");
  capflow::output::write_vtp((d / "src.vtp").string(), sphere(5, 0.75));
  run_python(d, R"(
import os
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter
base = ')" + d.string() +
                    R"('
r = vtkXMLPolyDataReader(); r.SetFileName(os.path.join(base, 'src.vtp')); r.Update()
for name, mode, h64 in (('vtk_ascii.vtp', 0, False), ('vtk_bin32.vtp', 1, False), ('vtk_bin64.vtp', 1, True)):
    w = vtkXMLPolyDataWriter(); w.SetInputData(r.GetOutput()); w.SetFileName(os.path.join(base, name))
    w.SetCompressorTypeToNone()
    w.SetDataMode(mode)
    if h64: w.SetHeaderTypeToUInt64()
    else: w.SetHeaderTypeToUInt32()
    assert w.Write() == 1
print('ok 1')
)");
  const VtkSurface s = sphere(5, 0.75);
  for (const char* f : {"vtk_ascii.vtp", "vtk_bin32.vtp", "vtk_bin64.vtp"}) {
    SCOPED_TRACE(f);
    const VtkSurface r = capflow::output::read_vtp((d / f).string());
    EXPECT_EQ(r.ne, 6);
    EXPECT_EQ(r.n, 5);
    EXPECT_DOUBLE_EQ(r.time, 0.75);
    ASSERT_EQ(r.x.size(), s.x.size());
    for (size_t k = 0; k < s.x.size(); ++k) EXPECT_NEAR(r.x[k], s.x[k], 1e-6);
    ASSERT_TRUE(r.point_arrays.count("tau1"));
    ASSERT_TRUE(r.point_arrays.count("velocity"));
    EXPECT_EQ(r.point_arrays.at("velocity").components, 3);
    for (size_t k = 0; k < s.point_arrays.at("tau1").values.size(); ++k)
      EXPECT_NEAR(r.point_arrays.at("tau1").values[k], s.point_arrays.at("tau1").values[k], 1e-6);
  }
}

TEST(Pvd, ValidAfterEveryAddResumesAndTruncates) {
  const fs::path d = fresh_dir("pvd");
  fs::create_directories(d / "vtk");
  const std::string pvd = (d / "surface.pvd").string();
  {
    PvdCollection c(pvd);
    EXPECT_TRUE(c.entries().empty());
    EXPECT_FALSE(fs::exists(pvd));  // nothing written before the first add
    for (int k = 0; k < 3; ++k) {
      const double t = 0.5 * k + 0.1;
      char name[64];
      std::snprintf(name, sizeof name, "vtk/surface_%06d.vtp", k);
      capflow::output::write_vtp((d / name).string(), sphere(4, t));
      c.add(t, name);
      const auto e = PvdCollection::read(pvd);  // valid at every moment
      ASSERT_EQ(e.size(), static_cast<size_t>(k + 1));
      EXPECT_EQ(e.back().time, t);
      EXPECT_EQ(e.back().file, name);
      EXPECT_FALSE(fs::exists(pvd + ".tmp"));
    }
  }
  {
    PvdCollection c(pvd);  // a resumed run continues the collection
    ASSERT_EQ(c.entries().size(), 3u);
    c.truncate_after(0.7);  // restart from t = 0.7: the entry at 1.1 goes
    ASSERT_EQ(PvdCollection::read(pvd).size(), 2u);
    capflow::output::write_vtp((d / "vtk/surface_000002.vtp").string(), sphere(4, 1.2));
    c.add(1.2, "vtk/surface_000002.vtp");
    c.add(1.2, "vtk/surface_000002.vtp");  // same file again: replaced, not duplicated
    EXPECT_EQ(PvdCollection::read(pvd).size(), 3u);
  }
  std::string why;
  if (!python_vtk_available(&why)) GTEST_SKIP() << "VTK reader check skipped: " << why;
  const auto kv = run_python(d, R"(
import os, xml.etree.ElementTree as ET
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
pvd = ')" + pvd + R"('
root = ET.parse(pvd).getroot()
assert root.tag == 'VTKFile' and root.get('type') == 'Collection'
sets = root.find('Collection').findall('DataSet')
print('count', len(sets))
for i, ds in enumerate(sets):
    r = vtkXMLPolyDataReader(); r.SetFileName(os.path.join(os.path.dirname(pvd), ds.get('file'))); r.Update()
    assert r.GetErrorCode() == 0
    tv = r.GetOutput().GetFieldData().GetArray('TimeValue').GetValue(0)
    print('t%d' % i, ds.get('timestep'), repr(tv), r.GetOutput().GetNumberOfPoints())
)");
  ASSERT_EQ(kv.at("count"), "3");
  const double expect[3] = {0.1, 0.6, 1.2};
  for (int i = 0; i < 3; ++i) {
    std::istringstream in(kv.at("t" + std::to_string(i)));
    double step = 0, tv = 0;
    long np = 0;
    in >> step >> tv >> np;
    EXPECT_EQ(step, expect[i]);
    EXPECT_EQ(tv, expect[i]);           // the file's own TimeValue matches its collection entry
    EXPECT_EQ(np, 6 * 4 + 12 * 2 + 8);  // 6 faces of 4 x 4 points, the edges welded
  }
}
