// capflow/serve/json_out: JSON text of numbers and strings for the API's answers (writing only:
// JSON is parsed in src/control alone). NaN and infinities are written as null.
#pragma once

#include <string>
#include <vector>

namespace capflow::serve {

std::string json_number(double v);
std::string json_string(const std::string& s);  // quoted, escaped (control characters as \u00XX)
std::string json_numbers(const std::vector<double>& v);  // [a, b, ...]

}  // namespace capflow::serve
