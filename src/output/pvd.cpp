// capflow/output/pvd: the ParaView collection (.pvd) that lists a run's surface files by time.
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "output/vtk.h"
#include "output/vtk_internal.h"

namespace capflow::output {
namespace fs = std::filesystem;

using detail::num;
using detail::parse_tag;
using detail::read_xml;
using detail::Tag;
using detail::write_atomic;

namespace {

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

}  // namespace

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

}  // namespace capflow::output
