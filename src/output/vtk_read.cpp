// capflow/output/vtk_read: reads ParaView surfaces (.vtp) through a small scanner for VTK's XML.
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "files/input_file.h"
#include "output/vtk.h"
#include "output/vtk_internal.h"

namespace capflow::output {

// ---- reading: a small scanner for the XML subset VTK PolyData files use ----

namespace {

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

// The first bytes of an XML file (after a UTF-8 byte order mark and white space): "<".
bool looks_like_xml(const std::string& head) {
  size_t i = head.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
  return i < head.size() && head[i] == '<';
}

}  // namespace

namespace detail {

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

}  // namespace detail

using detail::kGridArray;
using detail::parse_tag;
using detail::read_xml;
using detail::Tag;

namespace {

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

long attr_long(const Tag& t, const char* key, long dflt) {
  auto it = t.attr.find(key);
  return it == t.attr.end() ? dflt : std::atol(it->second.c_str());
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

}  // namespace capflow::output
