#include "output/vtk.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include "files/atomic_write.h"
#include "files/input_file.h"
#include "files/printable.h"

namespace capflow::output {
namespace fs = std::filesystem;

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

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      case '\'':
        o += "&apos;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

std::string xml_unescape(const std::string& s) {
  std::string o;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '&') {
      o += s[i];
      continue;
    }
    static const std::pair<const char*, char> ents[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    bool done = false;
    for (const auto& [e, c] : ents) {
      if (s.compare(i, std::strlen(e), e) == 0) {
        o += c;
        i += std::strlen(e) - 1;
        done = true;
        break;
      }
    }
    if (!done) o += '&';
  }
  return o;
}

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

// ---- reading: a small scanner for the XML subset VTK PolyData files use ----

struct Tag {
  std::string name;
  bool closing = false, self_closing = false;
  std::map<std::string, std::string> attr;
  size_t end = 0;  // position after '>'
};

// Parses the tag starting at s[pos] == '<'. Comments and declarations give an empty name.
Tag parse_tag(const std::string& s, size_t pos, const std::string& file) {
  Tag t;
  const size_t close = s.find('>', pos);
  if (close == std::string::npos) throw std::runtime_error("vtk: " + file + ": unterminated tag");
  t.end = close + 1;
  if (s.compare(pos, 4, "<!--") == 0) {
    const size_t e = s.find("-->", pos);
    if (e == std::string::npos) throw std::runtime_error("vtk: " + file + ": unterminated comment");
    t.end = e + 3;
    return t;
  }
  if (s[pos + 1] == '?' || s[pos + 1] == '!') return t;
  size_t i = pos + 1;
  if (s[i] == '/') {
    t.closing = true;
    ++i;
  }
  const size_t name_end = s.find_first_of(" \t\r\n/>", i);
  t.name = s.substr(i, name_end - i);
  i = name_end;
  while (i < close) {
    while (i < close && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i >= close) break;
    if (s[i] == '/') {
      t.self_closing = true;
      ++i;
      continue;
    }
    const size_t eq = s.find('=', i);
    if (eq == std::string::npos || eq > close)
      throw std::runtime_error("vtk: " + file + ": malformed attribute in <" + t.name + ">");
    std::string key = s.substr(i, eq - i);
    while (!key.empty() && std::isspace(static_cast<unsigned char>(key.back()))) key.pop_back();
    size_t q = eq + 1;
    while (q < close && std::isspace(static_cast<unsigned char>(s[q]))) ++q;
    const char quote = s[q];
    if (quote != '"' && quote != '\'')
      throw std::runtime_error("vtk: " + file + ": unquoted attribute " + key);
    const size_t qe = s.find(quote, q + 1);
    if (qe == std::string::npos || qe > close)
      throw std::runtime_error("vtk: " + file + ": unterminated attribute " + key);
    t.attr[key] = xml_unescape(s.substr(q + 1, qe - q - 1));
    i = qe + 1;
  }
  return t;
}

size_t type_size(const std::string& type) {
  if (type == "Float64" || type == "Int64" || type == "UInt64") return 8;
  if (type == "Float32" || type == "Int32" || type == "UInt32") return 4;
  if (type == "Int16" || type == "UInt16") return 2;
  if (type == "Int8" || type == "UInt8") return 1;
  return 0;
}

double value_at(const unsigned char* p, const std::string& type) {
  auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  if (type == "Float64") return get(double{});
  if (type == "Float32") return get(float{});
  if (type == "Int64") return get(int64_t{});
  if (type == "UInt64") return get(uint64_t{});
  if (type == "Int32") return get(int32_t{});
  if (type == "UInt32") return get(uint32_t{});
  if (type == "Int16") return get(int16_t{});
  if (type == "UInt16") return get(uint16_t{});
  if (type == "Int8") return get(int8_t{});
  return get(uint8_t{});
}

std::vector<double> decode_array(const Tag& t, const std::string& body, bool header64,
                                 const std::string& file) {
  const std::string name = t.attr.count("Name") ? t.attr.at("Name") : "(unnamed)";
  const std::string type = t.attr.count("type") ? t.attr.at("type") : "";
  const std::string format = t.attr.count("format") ? t.attr.at("format") : "ascii";
  const size_t ts = type_size(type);
  if (ts == 0)
    throw std::runtime_error("vtk: " + file + ": array " + name + ": unsupported type '" + type +
                             "'");
  std::vector<double> v;
  if (format == "ascii") {
    const char* p = body.c_str();
    char* end = nullptr;
    while (true) {
      while (*p && std::isspace(static_cast<unsigned char>(*p))) ++p;
      if (!*p) break;
      errno = 0;
      const double d = std::strtod(p, &end);
      if (end == p) throw std::runtime_error("vtk: " + file + ": array " + name + ": bad number");
      v.push_back(d);
      p = end;
    }
  } else if (format == "binary") {
    std::vector<unsigned char> raw;
    try {
      raw = base64_decode(body);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error("vtk: " + file + ": array " + name + ": " + e.what());
    }
    const size_t hs = header64 ? 8 : 4;
    if (raw.size() < hs)
      throw std::runtime_error("vtk: " + file + ": array " + name + ": truncated");
    uint64_t bytes = 0;
    if (header64)
      std::memcpy(&bytes, raw.data(), 8);
    else {
      uint32_t b32;
      std::memcpy(&b32, raw.data(), 4);
      bytes = b32;
    }
    if (bytes > raw.size() - hs || bytes % ts)
      throw std::runtime_error("vtk: " + file + ": array " + name + ": byte count " +
                               std::to_string(bytes) + " does not match its data");
    v.resize(bytes / ts);
    for (size_t k = 0; k < v.size(); ++k) v[k] = value_at(raw.data() + hs + k * ts, type);
  } else {
    throw std::runtime_error("vtk: " + file + ": array " + name + ": format '" + format +
                             "' not supported (ascii or inline binary only)");
  }
  return v;
}

// FieldData array of the element grids' welded point indices (write_vtp, read_vtp).
constexpr const char* kGridArray = "capflow_grid_point";

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

long attr_long(const Tag& t, const char* key, long dflt) {
  auto it = t.attr.find(key);
  return it == t.attr.end() ? dflt : std::atol(it->second.c_str());
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

namespace {

// The first bytes of an XML file (after a UTF-8 byte order mark and white space): "<".
bool looks_like_xml(const std::string& head) {
  size_t i = head.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
  return i < head.size() && head[i] == '<';
}

// A whole XML file read under files/input_file.h's rule, its first bytes checked first.
std::string read_xml(const std::string& path, const char* what, std::size_t max_bytes) {
  try {
    files::InputFile in(path, what, max_bytes);
    if (!looks_like_xml(in.read_prefix(256)))
      throw std::runtime_error("vtk: " + path + ": not a " + what +
                               " (an XML file starts with '<')");
    return in.read_all();
  } catch (const files::InputError& e) {
    throw std::runtime_error(std::string("vtk: ") + e.what());
  }
}

}  // namespace

VtkSurface read_vtp(const std::string& path) {
  return parse_vtp(read_xml(path, "ParaView surface", kMaxVtpBytes), path);
}

VtkSurface parse_vtp(const std::string& s, const std::string& path) {

  VtkSurface out;
  bool header64 = false, saw_file = false, saw_piece = false, have_points = false;
  long npoints = -1, npolys = -1;
  double ne = -1, n = -1;
  bool have_time = false;
  std::string section;  // innermost of FieldData, PointData, CellData, Points, Polys, ...
  std::vector<double> offsets, grid;
  size_t pos = 0;
  while ((pos = s.find('<', pos)) != std::string::npos) {
    const Tag t = parse_tag(s, pos, path);
    pos = t.end;
    if (t.name.empty()) continue;
    if (t.name == "VTKFile" && !t.closing) {
      saw_file = true;
      if (t.attr.count("type") && t.attr.at("type") != "PolyData")
        throw std::runtime_error("vtk: " + path + ": not a PolyData file");
      if (t.attr.count("compressor"))
        throw std::runtime_error("vtk: " + path + ": compressed files are not supported");
      if (t.attr.count("byte_order") && t.attr.at("byte_order") != "LittleEndian")
        throw std::runtime_error("vtk: " + path + ": big-endian files are not supported");
      header64 = t.attr.count("header_type") && t.attr.at("header_type") == "UInt64";
    } else if (t.name == "Piece" && !t.closing) {
      if (saw_piece) throw std::runtime_error("vtk: " + path + ": more than one Piece");
      saw_piece = true;
      npoints = attr_long(t, "NumberOfPoints", -1);
      npolys = attr_long(t, "NumberOfPolys", 0);
    } else if (t.name == "DataArray" && !t.closing) {
      std::string body;
      if (!t.self_closing) {
        const size_t e = s.find("</DataArray>", pos);
        if (e == std::string::npos)
          throw std::runtime_error("vtk: " + path + ": unterminated DataArray");
        body = s.substr(pos, e - pos);
        pos = e + std::strlen("</DataArray>");
        // VTK's writer nests <InformationKey> elements (e.g. the L2 norm range of normals)
        // before the data: drop them.
        for (size_t ik; (ik = body.find("<InformationKey")) != std::string::npos;) {
          const size_t gt = body.find('>', ik);
          size_t end = std::string::npos;
          if (gt != std::string::npos && body[gt - 1] == '/')
            end = gt + 1;
          else if (const size_t c = body.find("</InformationKey>", ik); c != std::string::npos)
            end = c + std::strlen("</InformationKey>");
          if (end == std::string::npos)
            throw std::runtime_error("vtk: " + path + ": unterminated InformationKey");
          body.erase(ik, end - ik);
        }
        if (body.find('<') != std::string::npos)
          throw std::runtime_error("vtk: " + path + ": unexpected element inside a DataArray");
      }
      std::vector<double> v = decode_array(t, body, header64, path);
      const std::string name = t.attr.count("Name") ? t.attr.at("Name") : "";
      const int comps = static_cast<int>(attr_long(t, "NumberOfComponents", 1));
      if (section == "FieldData") {
        if (name == kGridArray) {
          grid = std::move(v);
          continue;
        }
        if (v.size() != 1) continue;  // capflow writes one-tuple scalars and the grid only
        if (name == "TimeValue") {
          out.time = v[0];
          have_time = true;
        } else if (name == "ne")
          ne = v[0];
        else if (name == "n")
          n = v[0];
        else
          out.field_scalars[name] = v[0];
      } else if (section == "PointData") {
        if (name.empty()) throw std::runtime_error("vtk: " + path + ": unnamed point array");
        out.point_arrays[name] = VtkArray{comps, std::move(v)};
      } else if (section == "Points") {
        if (comps != 3)
          throw std::runtime_error("vtk: " + path + ": Points must have 3 components");
        out.x = std::move(v);
        have_points = true;
      } else if (section == "Polys" && name == "offsets") {
        offsets = std::move(v);
      }
    } else if (t.name == "FieldData" || t.name == "PointData" || t.name == "CellData" ||
               t.name == "Points" || t.name == "Polys" || t.name == "Verts" || t.name == "Lines" ||
               t.name == "Strips") {
      if (t.closing)
        section.clear();
      else if (!t.self_closing)
        section = t.name;
    }
  }
  if (!saw_file || !saw_piece)
    throw std::runtime_error("vtk: " + path + ": not a VTK PolyData file");
  if (!have_points) throw std::runtime_error("vtk: " + path + ": no Points");
  if (!(ne >= 1 && n >= 2 && ne <= kMaxVtpElements && n <= kMaxVtpGrid) ||
      ne != std::floor(ne) || n != std::floor(n))
    throw std::runtime_error("vtk: " + path + ": missing or bad field arrays ne, n (element grid: " +
                             "ne in [1, " + std::to_string(kMaxVtpElements) + "], n in [2, " +
                             std::to_string(kMaxVtpGrid) + "])");
  (void)have_time;
  out.ne = static_cast<int>(ne);
  out.n = static_cast<int>(n);
  if (static_cast<long>(out.x.size()) != 3 * npoints)
    throw std::runtime_error("vtk: " + path + ": Points do not hold NumberOfPoints " +
                             std::to_string(npoints) + " points");
  if (!grid.empty()) {
    // welded points (write_vtp): back to the element grids through the stored indices
    if (static_cast<long>(grid.size()) != out.num_points())
      throw std::runtime_error("vtk: " + path + ": " + kGridArray + " holds " +
                               std::to_string(grid.size()) +
                               " indices, not ne*n*n = " + std::to_string(out.num_points()));
    for (double g : grid)
      if (!(g >= 0 && g < npoints && g == std::floor(g)))
        throw std::runtime_error("vtk: " + path + ": " + kGridArray + " has an index outside [0, " +
                                 std::to_string(npoints) + ")");
    const auto expand = [&](std::vector<double>& v, int comps) {
      if (static_cast<long>(v.size()) != comps * npoints) return;  // IsValid names it below
      std::vector<double> e(grid.size() * comps);
      for (size_t k = 0; k < grid.size(); ++k)
        for (int c = 0; c < comps; ++c)
          e[k * comps + c] = v[static_cast<size_t>(grid[k]) * comps + c];
      v = std::move(e);
    };
    expand(out.x, 3);
    for (auto& [name, a] : out.point_arrays) expand(a.values, a.components);
  } else if (npoints != out.num_points()) {
    throw std::runtime_error("vtk: " + path + ": NumberOfPoints " + std::to_string(npoints) +
                             " does not match ne*n*n = " + std::to_string(out.num_points()));
  }
  if (npolys != out.num_cells() || static_cast<long>(offsets.size()) != npolys)
    throw std::runtime_error("vtk: " + path + ": expected " + std::to_string(out.num_cells()) +
                             " quads");
  for (size_t c = 0; c < offsets.size(); ++c)
    if (offsets[c] != 4.0 * (c + 1))
      throw std::runtime_error("vtk: " + path + ": cells are not quads");
  std::string err;
  if (!out.IsValid(&err)) throw std::runtime_error("vtk: " + path + ": " + err);
  return out;
}

PvdCollection::PvdCollection(std::string pvd_path) : path_(std::move(pvd_path)) {
  if (fs::exists(path_)) entries_ = read(path_);
}

void PvdCollection::add(double time, const std::string& file) {
  bool replaced = false;
  for (auto& e : entries_)
    if (e.file == file) {
      e.time = time;
      replaced = true;
    }
  if (!replaced) entries_.push_back({time, file});
  write();
}

void PvdCollection::truncate_after(double t) {
  std::vector<PvdEntry> keep;
  for (const auto& e : entries_)
    if (e.time <= t) keep.push_back(e);
  entries_.swap(keep);
  write();
}

void PvdCollection::write() const {
  std::string o = "<?xml version=\"1.0\"?>\n";
  o += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  o += "  <Collection>\n";
  for (const auto& e : entries_)
    o += "    <DataSet timestep=\"" + num(e.time) + "\" group=\"\" part=\"0\" file=\"" +
         xml_escape(e.file) + "\"/>\n";
  o += "  </Collection>\n</VTKFile>\n";
  write_atomic(path_, o);
}

std::vector<PvdEntry> PvdCollection::read(const std::string& pvd_path) {
  return parse(read_xml(pvd_path, "ParaView collection", kMaxPvdBytes), pvd_path);
}

std::vector<PvdEntry> PvdCollection::parse(const std::string& s, const std::string& pvd_path) {
  std::vector<PvdEntry> out;
  bool collection = false;
  size_t pos = 0;
  while ((pos = s.find('<', pos)) != std::string::npos) {
    const Tag t = parse_tag(s, pos, pvd_path);
    pos = t.end;
    if (t.name == "Collection") collection = true;
    if (t.name != "DataSet" || t.closing) continue;
    if (!t.attr.count("file"))
      throw std::runtime_error("vtk: " + pvd_path + ": DataSet without a file attribute");
    PvdEntry e;
    e.file = t.attr.at("file");
    if (t.attr.count("timestep")) {
      char* end = nullptr;
      const std::string& v = t.attr.at("timestep");
      e.time = std::strtod(v.c_str(), &end);
      if (end == v.c_str())
        throw std::runtime_error("vtk: " + pvd_path + ": bad timestep '" + v + "'");
    }
    out.push_back(e);
  }
  if (!collection) throw std::runtime_error("vtk: " + pvd_path + ": not a .pvd collection");
  return out;
}

std::string base64_encode(const void* data, size_t bytes) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string o;
  o.reserve((bytes + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes; i += 3) {
    const uint32_t v = (p[i] << 16) | (p[i + 1] << 8) | p[i + 2];
    o += tbl[v >> 18];
    o += tbl[(v >> 12) & 63];
    o += tbl[(v >> 6) & 63];
    o += tbl[v & 63];
  }
  if (i < bytes) {
    const uint32_t v = (p[i] << 16) | (i + 1 < bytes ? p[i + 1] << 8 : 0);
    o += tbl[v >> 18];
    o += tbl[(v >> 12) & 63];
    o += i + 1 < bytes ? tbl[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

std::vector<unsigned char> base64_decode(const std::string& text) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  out.reserve(text.size() * 3 / 4);
  uint32_t acc = 0;
  int bits = 0;
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (c == '=') {
      // Padding ends a group; VTK may start a new base64 block right after it.
      acc = 0;
      bits = 0;
      continue;
    }
    const int v = val(c);
    if (v < 0)
      throw std::runtime_error("base64: invalid character '" +
                               files::printable(std::string_view(&c, 1)) + "'");
    acc = (acc << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((acc >> bits) & 0xFF));
    }
  }
  return out;
}

}  // namespace capflow::output
