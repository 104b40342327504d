// capflow/output/vtk_internal: what the ParaView writer and readers share (internal to src/output).
#pragma once

#include <cstddef>
#include <map>
#include <string>

namespace capflow::output::detail {

// FieldData array of the element grids' welded point indices (write_vtp, read_vtp).
inline constexpr const char* kGridArray = "capflow_grid_point";

// A double as text that reads back bit for bit (%.17g); vtk.cpp.
std::string num(double v);
// <path>.tmp renamed over <path>, failures as std::runtime_error "vtk: ..."; vtk.cpp.
void write_atomic(const std::string& path, const std::string& text);

// The XML scanner (vtk_read.cpp): one tag, and a whole XML file read with its first bytes checked.
struct Tag {
  std::string name;
  bool closing = false, self_closing = false;
  std::map<std::string, std::string> attr;
  size_t end = 0;  // position after '>'
};
Tag parse_tag(const std::string& s, size_t pos, const std::string& file);
std::string read_xml(const std::string& path, const char* what, std::size_t max_bytes);

}  // namespace capflow::output::detail
