// capflow/output/vtk: writes the ParaView surface (.vtp), its element grids' points welded.
#include "output/vtk.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include "files/atomic_write.h"
#include "output/vtk_internal.h"

namespace capflow::output {

namespace detail {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Writes `text` to <path>.tmp and renames it over <path> (files/atomic_write.h).
void write_atomic(const std::string& path, const std::string& text) {
  try {
    files::write_atomically(path, text);
  } catch (const files::WriteError& e) {
    throw std::runtime_error(std::string("vtk: ") + e.what());
  }
}

}  // namespace detail

using detail::kGridArray;
using detail::num;
using detail::write_atomic;

namespace {

bool little_endian_host() {
  const uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

bool xml_safe_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c == '<' || c == '>' || c == '&' || c == '"' || c == '\'' || c == '\n' || c == '\r')
      return false;
  return true;
}

template <class T>
void append_array(std::string* out, const std::vector<T>& v, const char* type,
                  const std::string& name, int components, VtkEncoding enc,
                  const std::string& indent, bool field_data = false) {
  std::string& o = *out;
  o += indent + "<DataArray type=\"" + type + "\"";
  if (!name.empty()) o += " Name=\"" + name + "\"";
  // VTK's reader sizes a FieldData array by its NumberOfTuples (0 when absent)
  if (field_data) o += " NumberOfTuples=\"" + std::to_string(v.size() / components) + "\"";
  o += " NumberOfComponents=\"" + std::to_string(components) + "\" format=\"";
  o += enc == VtkEncoding::Ascii ? "ascii\">\n" : "binary\">\n";
  if (enc == VtkEncoding::Ascii) {
    const size_t per_line = components == 1 ? 6 : components;
    for (size_t i = 0; i < v.size(); i += per_line) {
      o += indent + "  ";
      for (size_t k = i; k < std::min(v.size(), i + per_line); ++k) {
        if (k > i) o += ' ';
        if constexpr (std::is_floating_point_v<T>)
          o += num(v[k]);
        else
          o += std::to_string(v[k]);
      }
      o += '\n';
    }
  } else {
    // One base64 stream of [UInt64 byte count][raw little-endian values].
    const uint64_t bytes = v.size() * sizeof(T);
    std::string raw(sizeof bytes + bytes, '\0');
    std::memcpy(raw.data(), &bytes, sizeof bytes);
    if (bytes) std::memcpy(raw.data() + sizeof bytes, v.data(), bytes);
    o += indent + "  " + base64_encode(raw.data(), raw.size()) + "\n";
  }
  o += indent + "</DataArray>\n";
}

// Welding: the element grids' points that coincide (element edges and corners, equal to
// rounding) become one point. grid[k] is the welded index of grid point k; returns the number
// of welded points. Positions are hashed on a lattice of spacing tol (1e-9 of the bounding box
// diagonal) and compared with the 27 neighbouring cells, so a pair straddling a cell boundary
// is still found.
long weld(const std::vector<double>& x, std::vector<int64_t>* grid) {
  const long np = static_cast<long>(x.size() / 3);
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (long k = 0; k < np; ++k)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], x[3 * k + d]);
      hi[d] = std::max(hi[d], x[3 * k + d]);
    }
  double diag = 0;
  for (int d = 0; d < 3; ++d) diag += (hi[d] - lo[d]) * (hi[d] - lo[d]);
  const double tol = std::max(1e-9 * std::sqrt(diag), 1e-300);
  struct Key {
    int64_t a, b, c;
    bool operator==(const Key& o) const { return a == o.a && b == o.b && c == o.c; }
  };
  struct Hash {
    size_t operator()(const Key& k) const {
      return static_cast<size_t>(k.a * 73856093 ^ k.b * 19349663 ^ k.c * 83492791);
    }
  };
  std::unordered_map<Key, std::vector<int64_t>, Hash> cells;  // cell -> welded points in it
  std::vector<long> first;                                    // welded point -> a grid point
  grid->assign(static_cast<size_t>(np), -1);
  for (long k = 0; k < np; ++k) {
    const double* p = &x[3 * k];
    const Key key{static_cast<int64_t>(std::floor((p[0] - lo[0]) / tol)),
                  static_cast<int64_t>(std::floor((p[1] - lo[1]) / tol)),
                  static_cast<int64_t>(std::floor((p[2] - lo[2]) / tol))};
    int64_t found = -1;
    for (int da = -1; da <= 1 && found < 0; ++da)
      for (int db = -1; db <= 1 && found < 0; ++db)
        for (int dc = -1; dc <= 1 && found < 0; ++dc) {
          const auto it = cells.find({key.a + da, key.b + db, key.c + dc});
          if (it == cells.end()) continue;
          for (int64_t w : it->second) {
            const double* q = &x[3 * first[static_cast<size_t>(w)]];
            if (std::abs(p[0] - q[0]) <= tol && std::abs(p[1] - q[1]) <= tol &&
                std::abs(p[2] - q[2]) <= tol) {
              found = w;
              break;
            }
          }
        }
    if (found < 0) {
      found = static_cast<int64_t>(first.size());
      first.push_back(k);
      cells[key].push_back(found);
    }
    (*grid)[static_cast<size_t>(k)] = found;
  }
  return static_cast<long>(first.size());
}

// The mean over the grid points of each welded point of a tuple-major array; unit: 3-tuples
// (normals) whose mean over several copies is made unit length again. A point with one copy
// keeps its value bit for bit.
std::vector<double> welded_mean(const std::vector<double>& v, int comps,
                                const std::vector<int64_t>& grid, long nw, bool unit = false) {
  std::vector<double> out(static_cast<size_t>(nw) * comps, 0.0);
  std::vector<int> count(static_cast<size_t>(nw), 0);
  for (size_t k = 0; k < grid.size(); ++k) {
    const size_t w = static_cast<size_t>(grid[k]);
    ++count[w];
    for (int c = 0; c < comps; ++c) out[w * comps + c] += v[k * comps + c];
  }
  for (size_t w = 0; w < count.size(); ++w) {
    if (count[w] == 1) continue;
    double* p = &out[w * comps];
    for (int c = 0; c < comps; ++c) p[c] /= count[w];
    if (unit && comps == 3) {
      const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      if (r > 0)
        for (int c = 0; c < 3; ++c) p[c] /= r;
    }
  }
  return out;
}

}  // namespace

bool VtkSurface::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (ne <= 0 || n < 2) return fail("vtk surface: ne must be > 0 and n >= 2");
  const size_t np = static_cast<size_t>(num_points());
  if (x.size() != 3 * np) return fail("vtk surface: x must hold 3*ne*n*n values");
  for (const auto& [name, a] : point_arrays) {
    if (!xml_safe_name(name)) return fail("vtk surface: bad point array name '" + name + "'");
    if (a.components < 1) return fail("vtk surface: array " + name + ": components must be >= 1");
    if (a.values.size() != np * static_cast<size_t>(a.components))
      return fail("vtk surface: array " + name +
                  " must hold components*ne*n*n = " + std::to_string(np * a.components) +
                  " values, has " + std::to_string(a.values.size()));
  }
  for (const auto& [name, v] : field_scalars) {
    (void)v;
    if (!xml_safe_name(name)) return fail("vtk surface: bad field name '" + name + "'");
    if (name == "TimeValue" || name == "ne" || name == "n")
      return fail("vtk surface: field name '" + name + "' is reserved");
  }
  return true;
}

void write_vtp(const std::string& path, const VtkSurface& s, VtkEncoding enc) {
  std::string err;
  if (!s.IsValid(&err)) throw std::runtime_error(err + " (writing " + path + ")");
  if (enc == VtkEncoding::Base64 && !little_endian_host())
    throw std::runtime_error("vtk: binary encoding needs a little-endian host (" + path + ")");
  const int n = s.n;
  const long nc = s.num_cells();
  std::vector<int64_t> grid;
  const long nw = weld(s.x, &grid);

  std::string o;
  o.reserve(static_cast<size_t>(nw) * 200);
  o += "<?xml version=\"1.0\"?>\n";
  o += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt64\">\n";
  o += "  <PolyData>\n    <FieldData>\n";
  auto field = [&](const std::string& name, double v) {
    o += "      <DataArray type=\"Float64\" Name=\"" + name +
         "\" NumberOfTuples=\"1\" format=\"ascii\">" + num(v) + "</DataArray>\n";
  };
  field("TimeValue", s.time);
  field("ne", s.ne);
  field("n", s.n);
  for (const auto& [name, v] : s.field_scalars) field(name, v);
  // the element grids' points as indices of the welded points: read_vtp restores the layout
  append_array(&o, grid, "Int64", kGridArray, 1, enc, "      ", true);
  o += "    </FieldData>\n";
  o += "    <Piece NumberOfPoints=\"" + std::to_string(nw) +
       "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
       std::to_string(nc) + "\">\n";
  o += "      <PointData";
  // Active attributes: ParaView colours by Scalars and shades with Normals by default.
  for (const char* sc : {"tau1", "tau2"}) {
    auto it = s.point_arrays.find(sc);
    if (it != s.point_arrays.end() && it->second.components == 1) {
      o += std::string(" Scalars=\"") + sc + "\"";
      break;
    }
  }
  if (auto it = s.point_arrays.find("Normals");
      it != s.point_arrays.end() && it->second.components == 3)
    o += " Normals=\"Normals\"";
  o += ">\n";
  for (const auto& [name, a] : s.point_arrays) {
    append_array(&o, welded_mean(a.values, a.components, grid, nw, name == "Normals"), "Float64",
                 name, a.components, enc, "        ");
  }
  o += "      </PointData>\n      <CellData>\n";
  std::vector<int32_t> element;
  element.reserve(static_cast<size_t>(nc));
  for (int e = 0; e < s.ne; ++e)
    element.insert(element.end(), static_cast<size_t>(n - 1) * (n - 1), e);
  append_array(&o, element, "Int32", "element", 1, enc, "        ");
  o += "      </CellData>\n      <Points>\n";
  append_array(&o, welded_mean(s.x, 3, grid, nw), "Float64", "Points", 3, enc, "        ");
  o += "      </Points>\n      <Polys>\n";
  std::vector<int64_t> conn, offs;
  conn.reserve(4 * static_cast<size_t>(nc));
  offs.reserve(static_cast<size_t>(nc));
  for (int e = 0; e < s.ne; ++e)
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        const size_t k = (static_cast<size_t>(e) * n + j) * n + i;
        conn.insert(conn.end(), {grid[k], grid[k + 1], grid[k + n + 1], grid[k + n]});
        offs.push_back(static_cast<int64_t>(conn.size()));
      }
  append_array(&o, conn, "Int64", "connectivity", 1, enc, "        ");
  append_array(&o, offs, "Int64", "offsets", 1, enc, "        ");
  o += "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
  write_atomic(path, o);
}

}  // namespace capflow::output
