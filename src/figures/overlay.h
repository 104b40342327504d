// capflow/figures/overlay: the x-y figure of quantities from each run's table (timeseries.csv
// or steady.csv): one data block per run, one series per (run, quantity).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "figures/figure.h"
#include "figures/run_tables.h"

namespace capflow::figures {

using RunTable = std::pair<RunInfo, Table>;

struct Quantity {
  std::string name;   // .dat column name
  std::string label;  // legend entry (enhanced text)
  std::function<double(const Table&, long)> f;
};

// A table column as a quantity (label: the given enhanced text, default the name as literal).
Quantity column(const std::string& name, const std::string& label = "");

struct OverlaySpec {
  std::string name, caption, paper, xlabel, ylabel;
  bool points = false;  // markers on the lines (sparse data: steady states)
};

// Rows with every value finite; runs without usable rows are named in the notes. Colour per run
// for one quantity, per quantity for several (style.h).
Figure overlay(const OverlaySpec& spec, const std::vector<RunTable>& data, const Quantity& x,
               const std::vector<Quantity>& ys);

// Whether any data block has rows (before references are added to a figure: a figure of
// references alone is not made).
bool has_rows(const Figure& fig);

// One more panel below the figure's last, drawing quantity y of the same runs against the same x
// (their blocks gain the column): e.g. Ca(t) under D(t).
void add_panel(Figure* fig, const std::vector<RunTable>& data, const Quantity& x, const Quantity& y,
               const std::string& ylabel);

}  // namespace capflow::figures
