#include "render/data_dir.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#ifndef CAPFLOW_DATA_SOURCE_DIR
#define CAPFLOW_DATA_SOURCE_DIR ""
#endif

namespace capflow::render {
namespace {
bool readable(const std::string& p) { return ::access(p.c_str(), R_OK) == 0; }

std::string exe_dir() {
  char buf[4096];
  ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return {};
  std::string p(buf, static_cast<size_t>(n));
  return p.substr(0, p.find_last_of('/'));
}
}  // namespace

std::string find_data_file(const std::string& relative) {
  std::vector<std::string> tried;
  if (const char* env = std::getenv("CAPFLOW_DATA_DIR"); env && *env) {
    std::string p = std::string(env) + "/" + relative;
    if (readable(p)) return p;
    throw std::runtime_error("missing data file '" + relative + "': not found at " + p +
                             " (CAPFLOW_DATA_DIR is set)");
  }
  std::string up = exe_dir();
  for (int k = 0; k < 3 && !up.empty(); ++k) {
    up += "/..";
    tried.push_back(up + "/" + relative);
  }
  if (*CAPFLOW_DATA_SOURCE_DIR) tried.push_back(std::string(CAPFLOW_DATA_SOURCE_DIR) + "/" + relative);
  for (const auto& p : tried)
    if (readable(p)) return p;
  std::string msg = "missing data file '" + relative + "'; tried:";
  for (const auto& p : tried) msg += " " + p;
  throw std::runtime_error(msg + " (set CAPFLOW_DATA_DIR to the directory holding shaders/ "
                           "and assets/)");
}

std::string read_data_file(const std::string& relative) {
  const std::string p = find_data_file(relative);
  std::ifstream f(p);
  if (!f) throw std::runtime_error("cannot read data file " + p);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace capflow::render
