// capflow/app/format: see format.h.
#include "app/format.h"

#include <iomanip>
#include <sstream>

namespace capflow::app {

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::string shortest(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace capflow::app
