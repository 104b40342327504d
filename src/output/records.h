// capflow/output/records: the layouts of the CSV files a run writes - their columns, units and
// number formats - in one place: the drivers write rows through them (format_row), the figures
// read the columns they name (src/figures), and docs/usage.md describes them.
//
//   timeseries.csv   capflow run, every output.csv_every: the state at t
//   steady.csv       capflow run: one row per steady state (the time the steady test fired)
//   steady.csv       capflow steady: one row per steady state solved for, with the solve's
//                    residual, node speed, volume drift and cost (kSteadySolve)
// Units: lengths in the capsule radius a, time in 1/G, tensions in Gs ("" dimensionless).
#pragma once

#include <string>
#include <vector>

namespace capflow::output::records {

struct Column {
  const char* name;
  const char* unit;    // "1/G", "a", "Gs", ...; "" dimensionless
  const char* format;  // printf format of its value: "%.10g", ... or "%ld" for a count
};

struct Layout {
  const char* file;  // the file's name in a run directory
  std::vector<Column> columns;
  std::string header() const;  // "t,ca,...\n"
  // The index of column `name` (std::invalid_argument for a name it does not have).
  std::size_t index(const std::string& name) const;
  bool has(const std::string& name) const;
};

const Layout& timeseries();    // capflow run's timeseries.csv
const Layout& steady_run();    // capflow run's steady.csv
const Layout& steady_solve();  // capflow steady's steady.csv

// One row (with its newline) of `values`, one per column, each in its column's format (a
// count's value is rounded to an integer). std::invalid_argument for a wrong count of values.
std::string format_row(const Layout& layout, const std::vector<double>& values);

}  // namespace capflow::output::records
