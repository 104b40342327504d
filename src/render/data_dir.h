// capflow/render/data_dir: locating run-time data (shaders/*.vert|frag, assets/*.csv).
//
// Search order for a relative name such as "shaders/surface.frag":
//   1. $CAPFLOW_DATA_DIR/<name>                      (override; if set, the ONLY place looked)
//   2. <dir of the executable>/../<name>, <dir>/../../<name>, <dir>/../../../<name>
//   3. <CAPFLOW_DATA_SOURCE_DIR>/<name>              (compile definition: the source tree)
// Failure: std::runtime_error naming the file and every path tried.
#pragma once

#include <string>

namespace capflow::render {

std::string find_data_file(const std::string& relative);
std::string read_data_file(const std::string& relative);  // whole file as text

}  // namespace capflow::render
