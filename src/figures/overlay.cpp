// capflow/figures/overlay: see overlay.h.
#include "figures/overlay.h"

#include <algorithm>
#include <cmath>

#include "figures/labels.h"
#include "figures/style.h"

namespace capflow::figures {

Quantity column(const std::string& name, const std::string& label) {
  return {name, label.empty() ? labels::literal(name) : label,
          [name](const Table& t, long r) { return t.num(r, t.col(name)); }};
}

namespace {

// Run r's block: x and the ys at every row where all are finite.
Block run_block(const RunTable& d, const Quantity& x, const std::vector<Quantity>& ys) {
  const auto& [run, tb] = d;
  Block b;
  b.comment = "run " + run.label + " (" + tb.source + ")";
  b.columns.push_back(x.name);
  for (const auto& y : ys) b.columns.push_back(y.name);
  for (long i = 0; i < tb.rows(); ++i) {
    std::vector<double> row{x.f(tb, i)};
    for (const auto& y : ys) row.push_back(y.f(tb, i));
    if (std::all_of(row.begin(), row.end(), [](double v) { return std::isfinite(v); }))
      b.rows.push_back(std::move(row));
  }
  return b;
}

}  // namespace

Figure overlay(const OverlaySpec& spec, const std::vector<RunTable>& data, const Quantity& x,
               const std::vector<Quantity>& ys) {
  Figure fig;
  fig.name = spec.name;
  fig.caption = spec.caption;
  fig.paper = spec.paper;
  fig.xlabel = spec.xlabel;
  fig.panels[0].ylabel = spec.ylabel;
  const bool per_quantity = ys.size() > 1;
  for (size_t r = 0; r < data.size(); ++r) {
    Block b = run_block(data[r], x, ys);
    if (b.rows.empty())
      fig.notes.push_back("run " + data[r].first.label + ": no usable rows in " +
                          data[r].second.source);
    fig.sources.push_back(data[r].second.source);
    const int block = static_cast<int>(fig.blocks.size());
    fig.blocks.push_back(std::move(b));
    const std::string run = labels::literal(data[r].first.label);
    for (size_t k = 0; k < ys.size(); ++k) {
      Series s;
      s.block = block;
      s.ycol = static_cast<int>(k) + 2;
      const int ri = static_cast<int>(r), ki = static_cast<int>(k);
      if (per_quantity) {
        s.title = data.size() == 1 ? ys[k].label : run + ": " + ys[k].label;
        s.style = style::data_line(ki, ri, ri, spec.points);
      } else {
        s.title = run;
        s.style = style::data_line(ri, 0, ri, spec.points);
      }
      fig.panels[0].series.push_back(s);
    }
  }
  return fig;
}

bool has_rows(const Figure& fig) {
  for (const Block& b : fig.blocks)
    if (!b.rows.empty()) return true;
  return false;
}

void add_panel(Figure* fig, const std::vector<RunTable>& data, const Quantity& x, const Quantity& y,
               const std::string& ylabel) {
  Panel p;
  p.ylabel = ylabel;
  for (size_t r = 0; r < data.size(); ++r) {
    Block b = run_block(data[r], x, {y});
    const int block = static_cast<int>(fig->blocks.size());
    b.comment += ", panel " + std::to_string(fig->panels.size() + 1);
    fig->blocks.push_back(std::move(b));
    Series s;
    s.block = block;
    s.title = labels::literal(data[r].first.label);
    s.style = style::data_line(static_cast<int>(r), 0, static_cast<int>(r), false);
    p.series.push_back(s);
  }
  fig->panels.push_back(std::move(p));
}

}  // namespace capflow::figures
