// capflow/output/records: see records.h.
#include "output/records.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <stdexcept>

namespace capflow::output::records {

namespace {
constexpr const char* kG = "%.10g";
}  // namespace

std::string Layout::header() const {
  std::string h;
  for (const Column& c : columns) h += (h.empty() ? "" : ",") + std::string(c.name);
  return h + "\n";
}

std::size_t Layout::index(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (name == columns[i].name) return i;
  throw std::invalid_argument(std::string(file) + " has no column " + name);
}

bool Layout::has(const std::string& name) const {
  for (const Column& c : columns)
    if (name == c.name) return true;
  return false;
}

namespace {

// The columns a layout is made of, in groups that several layouts share.
using Columns = std::vector<Column>;
const Columns kTimeAndCa{{"t", "1/G", kG}, {"ca", "", kG}};
const Columns kD{{"D", "", kG}};
const Columns kAxes{{"L", "a", kG},  {"S", "a", kG},  {"W", "a", kG},
                    {"Lc", "a", kG}, {"Sc", "a", kG}, {"Wc", "a", kG}};
const Columns kArea{{"area", "a^2", kG}};
const Columns kVolume{{"volume", "a^3", "%.12g"}};
const Columns kCurvatureAndTensions{
    {"edge_curvature", "1/a", kG}, {"tau_max", "Gs", kG}, {"tau_min", "Gs", kG}};

Layout layout(const char* file, std::initializer_list<Columns> groups) {
  Layout l{file, {}};
  for (const Columns& g : groups) l.columns.insert(l.columns.end(), g.begin(), g.end());
  return l;
}

}  // namespace

const Layout& timeseries() {
  static const Layout l =
      layout("timeseries.csv", {kTimeAndCa, kD, kAxes, kArea, kVolume, kCurvatureAndTensions,
                                {{"bending_energy", "Gs a^2", kG},
                                 {"inclination_deg", "deg", "%.8g"},
                                 {"volume_drift", "", "%.6e"},
                                 {"steps", "", "%ld"},
                                 {"dt", "1/G", "%.6g"},
                                 {"wall_s", "s", "%.3f"}}});
  return l;
}

const Layout& steady_run() {
  static const Layout l =
      layout("steady.csv", {kTimeAndCa, kAxes, kD, kArea, kCurvatureAndTensions});
  return l;
}

const Layout& steady_solve() {
  static const Layout l = layout("steady.csv", {steady_run().columns,
                                                 {{"residual", "a G", "%.3e"},
                                                  {"speed", "a G", "%.3e"},
                                                  {"volume_drift", "", "%.3e"},
                                                  {"newton", "", "%ld"},
                                                  {"krylov", "", "%ld"},
                                                  {"evaluations", "", "%ld"},
                                                  {"wall_s", "s", "%.3f"},
                                                  {"folds", "", "%ld"}}});
  return l;
}

std::string format_row(const Layout& layout, const std::vector<double>& values) {
  if (values.size() != layout.columns.size())
    throw std::invalid_argument(std::string(layout.file) + ": " + std::to_string(values.size()) +
                                " values for " + std::to_string(layout.columns.size()) +
                                " columns");
  std::string row;
  char buf[64];
  for (std::size_t i = 0; i < values.size(); ++i) {
    const char* f = layout.columns[i].format;
    if (std::strcmp(f, "%ld") == 0)
      std::snprintf(buf, sizeof buf, "%ld", std::lround(values[i]));
    else
      std::snprintf(buf, sizeof buf, f, values[i]);
    if (i) row += ',';
    row += buf;
  }
  return row + "\n";
}

}  // namespace capflow::output::records
