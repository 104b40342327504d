// capflow/figures/format: numbers and names as the figure files write them.
#pragma once

#include <string>

namespace capflow::figures {

std::string short_num(
    double v);  // 6 significant digits: legends, messages (2.9999999999998912 -> 3)
std::string exact_num(double v);  // the shortest text that reads back as the same double (.dat)
std::string safe_name(const std::string& s);  // a file-name-safe form of a run label
std::string time_tag(double t);               // "t0.5": 3-D view file names

}  // namespace capflow::figures
