// capflow/figures/figure: what a 2-D figure is, independent of how it is drawn.
//
// A Figure is data blocks (written to <name>.dat, gnuplot `index i`) and one or more panels
// stacked vertically that share the x axis; each panel draws series from the blocks. Labels are
// gnuplot enhanced text (figures/labels.h builds them); the caption goes to figures.md, not
// into the plot.
#pragma once

#include <string>
#include <vector>

namespace capflow::figures {

// What the figures know about a run: where it is, how it is labelled, and what the references
// need (law, flow). The app fills it from the run's control.json.
struct RunInfo {
  std::string dir, label;
  std::string law;   // "skalak", "neo-hookean", "mooney-rivlin"; empty if unknown
  double c = 1;      // Skalak's area-dilatation parameter C
  std::string flow;  // "planar-extension", "simple-shear", or another flow's name
  bool shear() const { return flow == "simple-shear"; }
};

struct Block {
  std::string comment;               // what the block holds (run, source file, time)
  std::vector<std::string> columns;  // column names
  std::vector<std::vector<double>> rows;
};

struct Series {
  int block = 0;
  int xcol = 1, ycol = 2;  // 1-based (gnuplot `using`)
  std::string title;       // legend entry, enhanced text ("" = no entry)
  std::string style;       // gnuplot style after `with`, e.g. "lines lw 2 lc rgb '#0072b2' dt 1"
};

struct Panel {
  std::string ylabel;  // enhanced text with the unit, e.g. "{/:Italic t} / G^{−1}"
  bool logy = false;
  std::vector<Series> series;
};

struct Figure {
  std::string name;     // file stem
  std::string caption;  // one sentence for figures.md (plain UTF-8)
  std::string paper;    // the paper's figures it corresponds to, e.g. "figs. 16, 17"
  std::string xlabel;   // enhanced text with the unit
  bool equal_aspect = false;
  std::vector<Block> blocks;
  std::vector<Panel> panels{Panel{}};
  std::vector<std::string> sources;  // files the data came from
  std::vector<std::string> notes;    // for figures.md
};

}  // namespace capflow::figures
