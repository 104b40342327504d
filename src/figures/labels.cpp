// capflow/figures/labels: see labels.h.
#include "figures/labels.h"

namespace capflow::figures::labels {

std::string literal(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '_' || c == '^' || c == '@' || c == '&' || c == '~' || c == '{' || c == '}' ||
        c == '\\')
      o += '\\';
    o += c;
  }
  return o;
}

std::string it(const std::string& s) {
  return "{/:Italic " + s + "}";
}

std::string time() {
  return it("t") + " / " + it("G") + "^{−1}";
}
std::string deformation() {
  return "Taylor deformation " + it("D");
}
std::string half_lengths() {
  return "half-lengths " + it("L") + ", " + it("S") + ", " + it("W") + " / " + it("a");
}
std::string capillary() {
  return "capillary number Ca";
}
std::string tension() {
  return "principal tension " + it("τ") + " / " + it("G") + "_s";
}
std::string curvature() {
  return "edge curvature " + it("κ") + " / " + it("a") + "^{−1}";
}
std::string volume_drift() {
  return "volume drift " + it("V") + " / " + it("V") + "_0 − 1";
}
std::string inclination() {
  return "inclination " + it("θ") + " / deg";
}
std::string area() {
  return "surface area " + it("A") + " / " + it("a") + "^2";
}
std::string coordinate(char axis) {
  return it(std::string(1, axis)) + " / " + it("a");
}

}  // namespace capflow::figures::labels
