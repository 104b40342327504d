// capflow/app/figure_args: the command line of `capflow figure` - its options, and every check
// of their values before a run directory is read (so that a bad option exits 2 naming it, and the
// option fuzzer can run the same checks: tests/fuzz/fuzz_options.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "app/render_flags.h"
#include "render/options.h"

namespace capflow::app {

struct FigureArgs {
  std::vector<std::string> runs;
  std::string out = "figures";
  std::vector<std::string> kinds{"timeseries", "profiles", "steady", "views"};
  std::vector<double> times;
  std::vector<std::string> labels;
  std::string vector = "svg";
  bool no_png = false, no_gnuplot = false, no_references = false;
  RenderFlags view = figure_view_flags();  // the 3-D views
  std::string view_name;                   // --view: instead of each run's camera

  static RenderFlags figure_view_flags() {
    RenderFlags f;
    f.width = 1200;
    f.height = 900;
    return f;
  }
};

// The most --times (and labels) a figure takes.
constexpr std::size_t kMaxFigureTimes = 1000;

void add_figure_args(CLI::App* sub, FigureArgs* a);

// Every option's value (UserError naming it): --vector, --kinds, --times (finite, at most
// kMaxFigureTimes), the 3-D views' image flags and --view; the renderer's options for the views.
// --labels against the runs is checked once sweeps are expanded (check_labels).
render::RenderOptions check_figure_args(const FigureArgs& a);
void check_labels(const FigureArgs& a);

}  // namespace capflow::app
