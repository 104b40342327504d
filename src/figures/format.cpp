// capflow/figures/format: see format.h.
#include "figures/format.h"

#include <cctype>
#include <cstdio>
#include <cstdlib>

namespace capflow::figures {

std::string short_num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string exact_num(double v) {
  char buf[40];
  for (int p : {10, 15, 17}) {
    std::snprintf(buf, sizeof buf, "%.*g", p, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string safe_name(const std::string& s) {
  std::string o;
  for (char c : s)
    o += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return o.empty() ? "run" : o;
}

std::string time_tag(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t%.4g", t);
  return buf;
}

}  // namespace capflow::figures
