// capflow/figures/run_tables: see run_tables.h.
#include "figures/run_tables.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "files/input_file.h"

namespace capflow::figures {

namespace fs = std::filesystem;

double Table::num(long row, int col) const {
  if (col < 0 || row < 0 || row >= rows()) return std::numeric_limits<double>::quiet_NaN();
  const auto& r = cells[static_cast<size_t>(row)];
  if (static_cast<size_t>(col) >= r.size()) return std::numeric_limits<double>::quiet_NaN();
  const std::string& s = r[static_cast<size_t>(col)];
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end == s.c_str()) return std::numeric_limits<double>::quiet_NaN();
  return v;
}

std::vector<double> Table::column(const std::string& name) const {
  const int c = col(name);
  if (c < 0) throw std::runtime_error(source + ": no column '" + name + "'");
  std::vector<double> v(static_cast<size_t>(rows()));
  for (long r = 0; r < rows(); ++r) v[static_cast<size_t>(r)] = num(r, c);
  return v;
}

Table read_csv(const std::string& path) {
  std::istringstream f;
  try {
    f.str(files::read_input_file(path, "CSV table", kMaxTableBytes));
  } catch (const files::InputError& e) {
    throw std::runtime_error(e.what());
  }
  Table t;
  t.source = path;
  std::string line;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::string cell;
    std::istringstream in(l);
    while (std::getline(in, cell, ',')) {
      while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
      size_t b = 0;
      while (b < cell.size() && cell[b] == ' ') ++b;
      out.push_back(cell.substr(b));
    }
    if (!l.empty() && l.back() == ',') out.emplace_back();
    return out;
  };
  if (!std::getline(f, line)) throw std::runtime_error(path + ": empty file (no header)");
  t.header = split(line);
  while (std::getline(f, line)) {
    if (line.empty() || line == "\r") continue;
    auto cells = split(line);
    if (cells.size() < t.header.size()) continue;
    t.cells.push_back(std::move(cells));
  }
  return t;
}

Profile read_profile(const std::string& path) {
  const Table tb = read_csv(path);
  const int cp = tb.col("plane"), ct = tb.col("t"), ca = tb.col("a"), cb = tb.col("b");
  if (cp < 0 || ct < 0 || ca < 0 || cb < 0)
    throw std::runtime_error(path + ": header must be plane,t,a,b");
  Profile p;
  p.file = path;
  p.t = std::numeric_limits<double>::quiet_NaN();
  for (long r = 0; r < tb.rows(); ++r) {
    const std::string& plane = tb.cells[static_cast<size_t>(r)][static_cast<size_t>(cp)];
    const double a = tb.num(r, ca), b = tb.num(r, cb);
    if (!std::isfinite(a) || !std::isfinite(b)) continue;
    if (std::isnan(p.t)) p.t = tb.num(r, ct);
    if (plane == "z")
      p.z.emplace_back(a, b);
    else if (plane == "y")
      p.y.emplace_back(a, b);
  }
  if (std::isnan(p.t)) throw std::runtime_error(path + ": no profile points");
  const std::string stem = fs::path(path).stem().string();  // profile_NNNNNN
  const auto us = stem.rfind('_');
  if (us != std::string::npos) p.index = std::atol(stem.c_str() + us + 1);
  return p;
}

std::vector<ProfileRef> list_profiles(const std::string& run_dir) {
  std::vector<ProfileRef> out;
  const fs::path d = fs::path(run_dir) / "profiles";
  if (!fs::is_directory(d)) return out;
  for (const auto& e : fs::directory_iterator(d)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("profile_", 0) != 0 || e.path().extension() != ".csv") continue;
    if (out.size() >= kMaxProfiles) break;
    try {
      const Profile p = read_profile(e.path().string());
      out.push_back({p.index, p.t, e.path().string()});
    } catch (const std::exception&) {
      // A file being written (or damaged) is left out.
    }
  }
  std::sort(out.begin(), out.end(),
            [](const ProfileRef& a, const ProfileRef& b) { return a.index < b.index; });
  return out;
}

long nearest(const std::vector<double>& ts, double t) {
  long best = -1;
  for (size_t i = 0; i < ts.size(); ++i)
    if (best < 0 || std::abs(ts[i] - t) < std::abs(ts[static_cast<size_t>(best)] - t))
      best = static_cast<long>(i);
  return best;
}

}  // namespace capflow::figures
