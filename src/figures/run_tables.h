// capflow/figures/run_tables: reading a run directory's tables back for the figures.
//
// What is read (all written by the run driver, see app/simulation.h):
//   timeseries.csv, steady.csv         numeric CSV with a header row (read_csv)
//   profiles/profile_NNNNNN.csv        plane,t,a,b: plane "z" -> (a,b) = (x,y), "y" -> (x,z);
//                                      profile NNNNNN shares its index with frame NNNNNN
//
// Every file is read under files/input_file.h's rule: a regular file (a FIFO or device is refused
// without blocking) of at most kMaxTableBytes; list_profiles looks at kMaxProfiles files at most.
//
// Failure: read_csv/read_profile throw std::runtime_error naming the file; list_profiles leaves
// out files it cannot read (a file being written).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace capflow::figures {

// The largest table read (a million rows of timeseries.csv), and the most profiles listed.
constexpr std::size_t kMaxTableBytes = std::size_t{256} << 20;
constexpr std::size_t kMaxProfiles = 100000;

struct Table {
  std::string source;                           // the file read
  std::vector<std::string> header;              // column names
  std::vector<std::vector<std::string>> cells;  // rows of text cells

  long rows() const { return static_cast<long>(cells.size()); }
  int col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  }
  // Numeric value of a cell; NaN for an empty or non-numeric cell.
  double num(long row, int col) const;
  // Throws naming the file when the column is missing.
  std::vector<double> column(const std::string& name) const;
};

// Comma-separated, first line the header, no quoting (capflow writes none). Blank lines are
// skipped; a row with fewer cells than the header (a line being written) is dropped.
Table read_csv(const std::string& path);

struct Profile {
  std::string file;
  long index = -1;  // NNNNNN of profile_NNNNNN.csv (= the frame index)
  double t = 0;
  std::vector<std::pair<double, double>> z;  // plane z = z_c: (x, y)
  std::vector<std::pair<double, double>> y;  // plane y = y_c: (x, z)
};

Profile read_profile(const std::string& path);

// (index, t, path) of every readable profile file, sorted by index.
struct ProfileRef {
  long index;
  double t;
  std::string file;
};
std::vector<ProfileRef> list_profiles(const std::string& run_dir);

// Index of the value in `ts` nearest to t (first of equals); -1 for an empty list.
long nearest(const std::vector<double>& ts, double t);

}  // namespace capflow::figures
