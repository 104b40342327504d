// capflow/output/vtk: ParaView export of the capsule surface. No solver types, no numerics:
// the caller hands over plain arrays.
//
// One call of write_vtp() writes one VTK XML PolyData file (".vtp", format version 1.0):
//   Points   : the element grids' points (VtkSurface::x, ne*n*n, point k = (e*n + j)*n + i, i
//              along xi, j along eta: the layout of render::Snapshot), welded: points that
//              coincide to 1e-9 of the bounding box diagonal (element edges and corners) are
//              written once, at the mean of their copies, so ParaView shades across the seams.
//              FieldData "capflow_grid_point" (Int64, ne*n*n) holds each grid point's welded
//              index: read_vtp restores the element grids (a welded point's values on every
//              copy: the mean, exact where the copies agreed).
//   Polys    : ne*(n-1)^2 quads (k(i,j), k(i+1,j), k(i+1,j+1), k(i,j+1)) through the welded
//              indices, ordered like the (xi, eta) parametrisation (counter-clockwise seen from
//              outside for the outward element maps). CellData "element" (Int32): each quad's
//              element (a point on an edge belongs to several elements, a quad to one).
//   PointData: every entry of point_arrays, Float64 with NumberOfComponents = components,
//              values tuple-major (value c of point k at [k*components + c]), the mean over a
//              welded point's copies ("Normals": made unit length again).
//              Conventional names (capflow's own writer uses them; load_surface reads them):
//              "tau1", "tau2" (principal tensions, 1 component), "dir1", "dir2" (principal
//              directions, 3), "Normals" (3), "velocity" (3).
//   FieldData: "TimeValue" (ParaView shows it as the time of a lone file), "ne", "n", and every
//              entry of field_scalars (e.g. "ca", "D"), each one Float64 tuple.
// Encoding: Ascii (%.17g, exact round trip) or Base64 (format="binary": per array one base64
// stream of [UInt64 byte count][little-endian data], header_type="UInt64", no compression).
// Files are written to "<path>.tmp" and renamed over <path> (readers never see half a file).
//
// PvdCollection keeps a ParaView collection file (".pvd") listing (time, file) pairs; add()
// rewrites it atomically, so the file is valid at every moment of a run. File names in the
// collection are relative to the .pvd's directory.
//
// Reading follows files/input_file.h's rule: a regular file of at most kMaxVtpBytes
// (kMaxPvdBytes), never blocking, whose first bytes must be XML before the rest is read.
//
// Failure: std::runtime_error naming the file (cannot write, invalid sizes on write; a special,
// too large or foreign file, missing or malformed parts on read).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace capflow::output {

struct VtkArray {
  int components = 1;          // values per point (1 scalar, 3 vector)
  std::vector<double> values;  // components * number of points, tuple-major
};

struct VtkSurface {
  int ne = 0;             // number of elements
  int n = 0;              // grid points per element direction (NB, or an upsampled count)
  double time = 0;        // simulated time, written as FieldData "TimeValue"
  std::vector<double> x;  // 3 * ne*n*n point coordinates (x, y, z per point)
  std::map<std::string, VtkArray> point_arrays;  // optional: any name, any component count
  std::map<std::string, double> field_scalars;   // optional: e.g. "ca", "D", "tau_max"

  long num_points() const { return static_cast<long>(ne) * n * n; }
  long num_cells() const { return static_cast<long>(ne) * (n - 1) * (n - 1); }
  // Sizes consistent (ne > 0, n >= 2, x and every array sized for num_points(), components
  // >= 1, names non-empty and free of XML special characters).
  bool IsValid(std::string* error) const;
};

enum class VtkEncoding { Ascii, Base64 };

// What read_vtp and PvdCollection::read take: capflow writes at most about 30 MiB per surface
// (NE=14 at 64 points per element edge, ascii) and 100 bytes per collection entry.
constexpr std::size_t kMaxVtpBytes = std::size_t{256} << 20;
constexpr std::size_t kMaxPvdBytes = std::size_t{64} << 20;
constexpr int kMaxVtpElements = 1000;  // the field array "ne"
constexpr int kMaxVtpGrid = 1000;      // the field array "n"

void write_vtp(const std::string& path, const VtkSurface& s,
               VtkEncoding encoding = VtkEncoding::Base64);

// Reads a file written by write_vtp (either encoding) back: ne, n, time, x, every point array
// and every one-tuple field array (except "TimeValue", "ne", "n", which fill the members).
// Also accepts other uncompressed, inline (ascii or binary) PolyData files with quads,
// if they carry the "ne" and "n" field arrays. Throws std::runtime_error naming the file.
VtkSurface read_vtp(const std::string& path);
// The same on text in memory; `path` names it in messages.
VtkSurface parse_vtp(const std::string& text, const std::string& path);

struct PvdEntry {
  double time = 0;
  std::string file;  // relative to the .pvd's directory
};

class PvdCollection {
 public:
  // Opens the collection <pvd_path>. An existing file is read (so a resumed run appends to it);
  // a missing file starts an empty collection (nothing is written until add()).
  explicit PvdCollection(std::string pvd_path);

  // Appends (time, file) and rewrites the .pvd atomically. An entry with the same file name is
  // replaced.
  void add(double time, const std::string& file);
  // Drops the entries with time > t (after a restart from an earlier checkpoint) and rewrites.
  void truncate_after(double t);

  const std::vector<PvdEntry>& entries() const { return entries_; }
  const std::string& path() const { return path_; }

  // Parses a .pvd (any DataSet elements with timestep and file attributes), in file order.
  static std::vector<PvdEntry> read(const std::string& pvd_path);
  static std::vector<PvdEntry> parse(const std::string& text, const std::string& pvd_path);

 private:
  void write() const;
  std::string path_;
  std::vector<PvdEntry> entries_;
};

// Base64 (RFC 4648, with '=' padding) used by the binary encoding; exposed for tests.
std::string base64_encode(const void* data, size_t bytes);
std::vector<unsigned char> base64_decode(const std::string& text);  // skips whitespace

}  // namespace capflow::output
