// capflow/app/format: numbers in the lines capflow says (run.log, the console).
#pragma once

#include <string>

namespace capflow::app {

// v with `digits` digits after the point ("0.4812").
std::string fixed(double v, int digits);
// v as an ostream prints it by default (6 significant digits: "0.001", "1e-07").
std::string shortest(double v);

}  // namespace capflow::app
