// capflow/figures/style: see style.h.
#include "figures/style.h"

namespace capflow::figures::style {

namespace {
const char* kColours[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                          "#e69f00", "#56b4e9", "#000000"};
const int kDashes[] = {1, 2, 4, 5, 3};
const int kPoints[] = {7, 5, 9, 11, 13, 6, 4, 8};

template <class T, int N>
T cycle(const T (&a)[N], int k) {
  return a[((k % N) + N) % N];
}
}  // namespace

std::string colour(int k) {
  return std::string("rgb '") + cycle(kColours, k) + "'";
}
std::string dash(int k) {
  return "dt " + std::to_string(cycle(kDashes, k));
}
std::string point(int k) {
  return "pt " + std::to_string(cycle(kPoints, k));
}

std::string data_line(int c, int d, int m, bool points) {
  return std::string(points ? "linespoints " + point(m) + " ps 0.8" : "lines") + " lw 2 lc " +
         colour(c) + " " + dash(d);
}

std::string theory_line(int k) {
  return "lines lw 1.5 lc rgb '#555555' " + dash(k + 1);
}

std::string published_points(int k) {
  static const int kOpen[] = {4, 6, 8, 10, 12};
  return "points pt " + std::to_string(cycle(kOpen, k)) + " ps 1.4 lw 1.5 lc rgb '#000000'";
}

}  // namespace capflow::figures::style
