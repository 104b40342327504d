// capflow/figures/gnuplot: a Figure as a gnuplot script and its data file.
//
// The script is meant to be edited and re-run (`gnuplot <name>.gp`): it draws no title (the
// caption is in figures.md), labels every axis with its symbol and unit (enhanced text, UTF-8),
// leaves a margin around the data (autoscale to the data, then offsets of a few % of the range),
// puts the legend below the plot where it cannot hide data, and stacks a figure's panels with a
// shared x axis. It writes <name>.svg (or .pdf) and, unless told not to, <name>.png.
#pragma once

#include <string>

#include "figures/figure.h"

namespace capflow::figures {

std::string dat_text(const Figure& fig);  // <name>.dat: one block per data set
std::string gp_script(const Figure& fig, const std::string& vector_format, bool png);
std::string gnuplot_quote(const std::string& s);  // a gnuplot single-quoted string

}  // namespace capflow::figures
