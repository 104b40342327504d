// capflow/app/figure_args: see figure_args.h.
#include "app/figure_args.h"

#include <cmath>
#include <set>
#include <sstream>

#include "app/errors.h"

namespace capflow::app {

void add_figure_args(CLI::App* sub, FigureArgs* c) {
  sub->add_option(
         "runs", c->runs,
         "run directories (several: overlaid / compared), or a sweep directory (its cases)")
      ->required();
  sub->add_option("-o,--output", c->out, "output directory (created)");
  sub->add_option("--kinds", c->kinds, "timeseries,profiles,steady,views (default all)")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--times", c->times,
                  "T1,T2,...: times of profiles and 3-D views (nearest available); default "
                  "profiles: 4 spread over the run, views: the last saved time")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--labels", c->labels, "legend labels, one per run (default: directory names)")
      ->delimiter(',')
      ->allow_extra_args(false);
  sub->add_option("--vector", c->vector, "vector format: svg | pdf");
  sub->add_flag("--no-png", c->no_png, "no PNG beside the vector image");
  sub->add_flag("--no-gnuplot", c->no_gnuplot, "write the .gp/.dat files without running gnuplot");
  sub->add_flag("--no-references", c->no_references,
                "leave out the theory lines and published values drawn where they apply");
  add_render_flags(sub, &c->view, "3-D view ");
  sub->add_option("--view", c->view_name,
                  "3-D views from oblique | xy | xz | yz (default: each run's render.view)");
}

render::RenderOptions check_figure_args(const FigureArgs& c) {
  if (c.out.empty()) throw UserError("-o: give an output directory");
  if (c.vector != "svg" && c.vector != "pdf")
    throw UserError("--vector " + c.vector + ": unknown format (svg | pdf)");
  const std::set<std::string> known{"timeseries", "profiles", "steady", "views"};
  for (const auto& k : c.kinds)
    if (!known.count(k))
      throw UserError("--kinds " + k + ": unknown (timeseries, profiles, steady, views)");
  if (c.times.size() > kMaxFigureTimes)
    throw UserError("--times: " + std::to_string(c.times.size()) + " times, at most " +
                    std::to_string(kMaxFigureTimes));
  for (double t : c.times)
    if (!std::isfinite(t)) {
      std::ostringstream m;
      m << "--times " << t << ": every time must be a finite number";
      throw UserError(m.str());
    }
  if (c.labels.size() > kMaxFigureTimes)
    throw UserError("--labels: " + std::to_string(c.labels.size()) + " labels, at most " +
                    std::to_string(kMaxFigureTimes));
  using namespace capflow::render;
  RenderOptions o;
  apply_render_flags(c.view, &o);
  o.png = o.mp4 = false;
  if (!c.view_name.empty() && !parse_view(c.view_name, &o.camera.view))
    throw UserError("--view " + c.view_name + ": unknown (oblique | xy | xz | yz)");
  std::string err;
  if (!o.IsValid(&err)) throw UserError(err);
  return o;
}

void check_labels(const FigureArgs& c) {
  if (!c.labels.empty() && c.labels.size() != c.runs.size())
    throw UserError("--labels needs one label per run directory (" + std::to_string(c.runs.size()) +
                    "), got " + std::to_string(c.labels.size()));
}

}  // namespace capflow::app
