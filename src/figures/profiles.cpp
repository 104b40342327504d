// capflow/figures/profiles: the profile kinds (kinds.h), from each run's profiles/*.csv (the
// shape's cuts with the planes z = 0 and y = 0 at the frame times).
#include <algorithm>
#include <cmath>
#include <set>

#include "figures/format.h"
#include "figures/kinds.h"
#include "figures/labels.h"
#include "figures/style.h"

namespace capflow::figures {

namespace {

Block unit_circle() {
  Block b;
  b.comment = "undisturbed profile: unit circle";
  b.columns = {"a", "b"};
  const int n = 200;
  for (int k = 0; k <= n; ++k) {
    const double th = 2 * M_PI * k / n;
    b.rows.push_back({std::cos(th), std::sin(th)});
  }
  return b;
}

Block profile_block(const Profile& p, char plane, const std::string& label) {
  Block b;
  b.comment = label + "t = " + short_num(p.t) + ", plane " + plane + " = 0 (" + p.file +
              "; first point repeated to close the curve)";
  b.columns = {"a", "b"};
  const auto& pts = plane == 'z' ? p.z : p.y;
  for (const auto& [a, c] : pts) b.rows.push_back({a, c});
  if (!b.rows.empty()) b.rows.push_back(b.rows.front());
  return b;
}

// Indices into ts for the requested times (nearest, deduplicated, in time order); default:
// up to four evenly spaced profiles including the first and the last.
std::vector<size_t> pick(const std::vector<double>& ts, const std::vector<double>& want) {
  std::set<size_t> s;
  if (ts.empty()) return {};
  if (want.empty()) {
    const size_t n = ts.size(), k = std::min<size_t>(4, n);
    for (size_t i = 0; i < k; ++i) s.insert(k == 1 ? n - 1 : i * (n - 1) / (k - 1));
  } else {
    for (double t : want) s.insert(static_cast<size_t>(nearest(ts, t)));
  }
  std::vector<size_t> v(s.begin(), s.end());
  std::sort(v.begin(), v.end(), [&](size_t a, size_t b) { return ts[a] < ts[b]; });
  return v;
}

// A profile figure's frame: the unit circle, equal axes, the plane's coordinates.
Figure profile_frame(const std::string& name, const std::string& caption, const std::string& paper,
                     char plane) {
  Figure f;
  f.name = name;
  f.caption = caption;
  f.paper = paper;
  f.xlabel = labels::coordinate('x');
  f.panels[0].ylabel = labels::coordinate(plane == 'z' ? 'y' : 'z');
  f.equal_aspect = true;
  f.blocks.push_back(unit_circle());
  f.panels[0].series.push_back({0, 1, 2, "undisturbed", "lines lw 1 lc rgb '#808080' dt 2"});
  return f;
}

}  // namespace

void profile_figures(Writer& w, const std::vector<RunInfo>& runs, const KindOptions& o) {
  struct Last {
    RunInfo run;
    Profile p;
  };
  std::vector<Last> last;
  for (const auto& run : runs) {
    const auto refs = list_profiles(run.dir);
    if (refs.empty()) {
      w.note("run " + run.label + ": no profiles/profile_NNNNNN.csv, no profile figures");
      continue;
    }
    std::vector<double> ts;
    for (const auto& r : refs) ts.push_back(r.t);
    std::vector<Profile> ps;
    for (size_t i : pick(ts, o.times)) ps.push_back(read_profile(refs[i].file));
    for (char plane : {'z', 'y'}) {
      Figure f = profile_frame("profiles_" + safe_name(run.label) + "_" + plane,
                               "Profile of run " + run.label + " in the plane " +
                                   std::string(1, plane) + " = 0 at several times",
                               plane == 'z' ? "figs. 6a, 7a, 12a" : "figs. 6b, 7b, 12b", plane);
      for (size_t k = 0; k < ps.size(); ++k) {
        f.blocks.push_back(profile_block(ps[k], plane, ""));
        const int ki = static_cast<int>(k);
        f.panels[0].series.push_back({ki + 1, 1, 2, labels::it("t") + " = " + short_num(ps[k].t),
                                      style::data_line(ki, 0, ki, false)});
        f.sources.push_back(ps[k].file);
      }
      for (double t : o.times) {
        const long i = nearest(ts, t);
        if (std::abs(ts[static_cast<size_t>(i)] - t) > 1e-9 * (1 + std::abs(t)))
          f.notes.push_back("requested t = " + short_num(t) + ": nearest available profile t = " +
                            short_num(ts[static_cast<size_t>(i)]));
      }
      w.emit(f);
    }
    const double want = o.times.empty() ? ts.back() : o.times.back();
    last.push_back({run, read_profile(refs[static_cast<size_t>(nearest(ts, want))].file)});
  }
  if (last.size() < 2) return;
  for (char plane : {'z', 'y'}) {
    Figure f = profile_frame(
        std::string("profiles_compare_") + plane,
        "Profiles of the runs compared in the plane " + std::string(1, plane) + " = 0", "fig. 15",
        plane);
    for (size_t k = 0; k < last.size(); ++k) {
      f.blocks.push_back(profile_block(last[k].p, plane, "run " + last[k].run.label + ", "));
      const int ki = static_cast<int>(k);
      f.panels[0].series.push_back({ki + 1, 1, 2,
                                    labels::literal(last[k].run.label) + " (" + labels::it("t") +
                                        " = " + short_num(last[k].p.t) + ")",
                                    style::data_line(ki, ki, ki, false)});
      f.sources.push_back(last[k].p.file);
    }
    w.emit(f);
  }
}

}  // namespace capflow::figures
