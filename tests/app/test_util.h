// Helpers for the app tests: temporary run directories, file reading, waiting.
#pragma once

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace capflow::test {

inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() /
                 ("capflow_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

inline std::vector<std::string> lines_of(const std::filesystem::path& p) {
  std::vector<std::string> out;
  std::ifstream f(p);
  std::string l;
  while (std::getline(f, l)) out.push_back(l);
  return out;
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::trunc);
  f << text;
}

// Polls pred every 20 ms for at most `seconds`.
inline bool wait_for(const std::function<bool()>& pred, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return pred();
}

// Column `name` of every data row of a CSV file (empty when the file or the column is missing).
inline std::vector<double> csv_column(const std::filesystem::path& csv, const std::string& name) {
  const std::vector<std::string> lines = lines_of(csv);
  std::vector<double> out;
  if (lines.empty()) return out;
  int col = -1, k = 0;
  std::stringstream header(lines[0]);
  for (std::string c; std::getline(header, c, ','); ++k)
    if (c == name) col = k;
  if (col < 0) return out;
  for (size_t i = 1; i < lines.size(); ++i) {
    std::stringstream row(lines[i]);
    std::string cell;
    for (int j = 0; j <= col && std::getline(row, cell, ','); ++j) {
    }
    out.push_back(std::stod(cell));
  }
  return out;
}

}  // namespace capflow::test
