// capflow/figures/gnuplot: see gnuplot.h.
#include "figures/gnuplot.h"

#include <sstream>

#include "figures/format.h"

namespace capflow::figures {

std::string gnuplot_quote(const std::string& s) {
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("''") : std::string(1, c);
  return o + "'";
}

std::string dat_text(const Figure& fig) {
  std::ostringstream o;
  o << "# capflow figure " << fig.name << ": " << fig.caption << "\n";
  o << "# one block per data set, separated by two blank lines (gnuplot: index i)\n";
  for (size_t b = 0; b < fig.blocks.size(); ++b) {
    const Block& bl = fig.blocks[b];
    o << "# block " << b << ": " << bl.comment << "\n# columns:";
    for (const auto& c : bl.columns) o << " " << c;
    o << "\n";
    for (const auto& r : bl.rows) {
      for (size_t k = 0; k < r.size(); ++k) o << (k ? " " : "") << exact_num(r[k]);
      o << "\n";
    }
    o << "\n\n";
  }
  return o.str();
}

namespace {

// The settings every terminal shares.
std::string common_settings(const Figure& fig) {
  std::ostringstream o;
  o << "set encoding utf8\n";
  o << "set minussign\n";  // tick labels with a true minus (U+2212)
  o << "set border lw 1.2\n";
  o << "set grid lc rgb '#d0d0d0' lw 1\n";
  o << "set tics nomirror out scale 0.6\n";
  o << "set xlabel " << gnuplot_quote(fig.xlabel) << "\n";
  // the data's own range, then a margin of a few % on every side
  o << "set autoscale fix\n";
  o << "set offsets graph 0.03, graph 0.03, graph 0.06, graph 0.06\n";
  if (fig.equal_aspect) o << "set size ratio -1\n";
  o << "dat = " << gnuplot_quote(fig.name + ".dat") << "\n";
  return o.str();
}

std::string plot_panel(const Panel& p, bool with_key) {
  std::ostringstream o;
  o << "set ylabel " << gnuplot_quote(p.ylabel) << "\n";
  o << (p.logy ? "set logscale y\n" : "unset logscale y\n");
  if (with_key)
    o << "set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque "
         "nobox\n";
  else
    o << "unset key\n";
  o << "plot \\\n";
  for (size_t i = 0; i < p.series.size(); ++i) {
    const Series& s = p.series[i];
    o << "  dat index " << s.block << " using " << s.xcol << ":" << s.ycol << " with " << s.style
      << (s.title.empty() ? " notitle" : " title " + gnuplot_quote(s.title))
      << (i + 1 < p.series.size() ? ", \\\n" : "\n");
  }
  return o.str();
}

// The plot commands for one terminal: one panel, or the panels stacked with the x axis shared
// (its label and the legend on the lowest panel only).
std::string plot_commands(const Figure& fig) {
  if (fig.panels.size() == 1) return plot_panel(fig.panels[0], true);
  std::ostringstream o;
  const size_t n = fig.panels.size();
  o << "set multiplot layout " << n << ",1 margins 0.13,0.97,0.15,0.98 spacing 0,0.03\n";
  for (size_t i = 0; i < n; ++i) {
    const bool last = i + 1 == n;
    o << (last ? "set format x '%g'\nset xlabel " + gnuplot_quote(fig.xlabel) + "\n"
               : "set format x ''\nunset xlabel\n");
    o << plot_panel(fig.panels[i], last);
  }
  o << "unset multiplot\n";
  return o.str();
}

}  // namespace

std::string gp_script(const Figure& fig, const std::string& vector_format, bool png) {
  std::ostringstream o;
  o << "# " << fig.name << ".gp: written by `capflow figure`; edit and re-run `gnuplot " << fig.name
    << ".gp`\n";
  o << "# " << fig.caption << (fig.paper.empty() ? "" : " (paper " + fig.paper + ")") << "\n";
  o << "# data: " << fig.name << ".dat (block i = index i)\n";
  for (const auto& s : fig.sources) o << "# source: " << s << "\n";
  o << common_settings(fig);
  const int tall = fig.panels.size() > 1 ? 1 : 0;  // stacked panels: a taller page
  o << "# vector image\n";
  if (vector_format == "pdf")
    o << "set terminal pdfcairo size 6in," << (tall ? "6in" : "4.5in")
      << " enhanced font 'DejaVu Sans,11'\n";
  else
    o << "set terminal svg size 800," << (tall ? 800 : 600)
      << " dynamic enhanced font 'DejaVu Sans,14' background '#ffffff'\n";
  o << "set output " << gnuplot_quote(fig.name + "." + vector_format) << "\n";
  o << plot_commands(fig);
  if (png) {
    o << "# raster image\n";
    o << "set terminal pngcairo size 1000," << (tall ? 1000 : 750)
      << " enhanced font 'DejaVu Sans,12' background '#ffffff'\n";
    o << "set output " << gnuplot_quote(fig.name + ".png") << "\n";
    o << plot_commands(fig);
  }
  o << "set output\n";
  return o.str();
}

}  // namespace capflow::figures
