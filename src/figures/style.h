// capflow/figures/style: line colours, dashes and point types.
//
// One colour per quantity when a figure draws several quantities (L, S, W), told apart in the
// legend by colour, with the runs told apart by dash and point type; one colour per run when it
// draws one quantity. Colours are the Okabe-Ito set (distinct for colour-blind readers and in
// grey print). References (theory lines, the paper's values) are black or grey.
#pragma once

#include <string>

namespace capflow::figures::style {

std::string colour(int k);  // "rgb '#0072b2'", cycling through 7 colours
std::string dash(int k);    // "dt 1", cycling through 5 dash types
std::string point(int k);   // "pt 7", cycling through filled and open markers

// A data line: colour c, dash d, with points (marker m) for sparse data such as steady states.
std::string data_line(int c, int d, int m, bool points);
// A reference: a theory line (grey, thin, dashed) or the published values of source k (black
// open markers: square, circle, triangle, ...).
std::string theory_line(int k);
std::string published_points(int k);

}  // namespace capflow::figures::style
