// capflow/figures/writer: see writer.h.
#include "figures/writer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "figures/format.h"
#include "figures/gnuplot.h"
#include "files/atomic_write.h"
#include "files/input_file.h"

namespace capflow::figures {

namespace fs = std::filesystem;

namespace {
std::string shell_quote(const std::string& s) {
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}

// The end of gnuplot's log (its own output, at most 2 KiB of it).
std::string log_tail(const fs::path& p) {
  try {
    const std::string s = files::read_input_file(p.string(), "gnuplot log", std::size_t{1} << 20);
    return s.size() > 2048 ? "..." + s.substr(s.size() - 2048) : s;
  } catch (const files::InputError& e) {
    return e.what();
  }
}

// Values gnuplot cannot draw (not finite, or so large that its ranges overflow) become NaN, which
// it skips; returns how many there were.
long drop_unplottable(Figure* f) {
  long n = 0;
  for (Block& b : f->blocks)
    for (auto& row : b.rows)
      for (double& v : row)
        if (!(std::abs(v) <= kMaxPlotValue)) {
          if (!std::isnan(v)) ++n;
          v = std::numeric_limits<double>::quiet_NaN();
        }
  return n;
}

// Empty blocks would shift gnuplot's `index` numbering (blank lines run together): drop them and
// renumber the series.
void drop_empty_blocks(Figure* f) {
  std::vector<int> index(f->blocks.size(), -1);
  std::vector<Block> kept;
  for (size_t b = 0; b < f->blocks.size(); ++b)
    if (!f->blocks[b].rows.empty()) {
      index[b] = static_cast<int>(kept.size());
      kept.push_back(std::move(f->blocks[b]));
    }
  f->blocks = std::move(kept);
  for (Panel& p : f->panels)
    for (Series& s : p.series) s.block = index[static_cast<size_t>(s.block)];
}
}  // namespace

bool gnuplot_on_path() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

void write_text(const fs::path& p, const std::string& text) {
  files::write_atomically(p.string(), text);
}

Writer::Writer(fs::path out, std::string vector_format, bool png, bool run_gnuplot, Say say)
    : out_(std::move(out)),
      vector_(std::move(vector_format)),
      say_(std::move(say)),
      png_(png),
      gnuplot_(run_gnuplot) {}

void Writer::note(const std::string& m) {
  say_("figure: " + m);
  manifest_ << "- note: " << m << "\n";
}

void Writer::record(const std::string& name, const std::string& entry) {
  manifest_ << entry << "\n";
  written_.push_back(name);
}

bool Writer::run_script(const Figure& f) {
  const fs::path log = out_ / (f.name + ".gnuplot.log");
  const std::string c = "cd " + shell_quote(out_.string()) + " && gnuplot " +
                        shell_quote(f.name + ".gp") + " > " + shell_quote(log.filename().string()) +
                        " 2>&1";
  const int rc = std::system(c.c_str());
  const fs::path vec = out_ / (f.name + "." + vector_);
  if (rc != 0 || !fs::exists(vec) || fs::file_size(vec) == 0) {
    note(f.name + ": gnuplot failed (exit " + std::to_string(rc) + "): " + log_tail(log));
    ++failures_;
    return false;
  }
  fs::remove(log);
  return true;
}

void Writer::emit(const Figure& fig) {
  // Series whose block is empty would make gnuplot fail: leave them out; a panel left without
  // series, or a figure without data, is skipped.
  Figure f = fig;
  const long left_out = drop_unplottable(&f);
  if (left_out > 0)
    f.notes.push_back(std::to_string(left_out) + " value(s) beyond +-" + short_num(kMaxPlotValue) +
                      " or not finite left out (gnuplot cannot draw them)");
  const auto empty = [&](const Series& s) {
    const Block& b = f.blocks[static_cast<size_t>(s.block)];
    for (const auto& row : b.rows) {
      const size_t x = static_cast<size_t>(s.xcol - 1), y = static_cast<size_t>(s.ycol - 1);
      if (x < row.size() && y < row.size() && std::isfinite(row[x]) && std::isfinite(row[y]))
        return false;
    }
    return true;
  };
  bool data = false;
  for (Panel& p : f.panels) {
    p.series.erase(std::remove_if(p.series.begin(), p.series.end(), empty), p.series.end());
    data = data || !p.series.empty();
  }
  f.panels.erase(std::remove_if(f.panels.begin(), f.panels.end(),
                                [](const Panel& p) { return p.series.empty(); }),
                 f.panels.end());
  if (!data) {
    note(fig.name + ": skipped, no data in any run");
    return;
  }
  drop_empty_blocks(&f);
  write_text(out_ / (f.name + ".dat"), dat_text(f));
  write_text(out_ / (f.name + ".gp"), gp_script(f, vector_, png_));
  std::string files = f.name + ".gp, " + f.name + ".dat";
  if (gnuplot_ && run_script(f))
    files += ", " + f.name + "." + vector_ + (png_ ? ", " + f.name + ".png" : "");
  say_("figure: " + f.name + " (" + files + ")");
  manifest_ << "- **" << f.name << "**: " << f.caption
            << (f.paper.empty() ? "" : " (paper " + f.paper + ")") << ". Files: " << files << ".";
  if (!f.sources.empty()) {
    manifest_ << " Sources:";
    for (const auto& s : f.sources) manifest_ << " " << s;
    manifest_ << ".";
  }
  manifest_ << "\n";
  for (const auto& n : f.notes) manifest_ << "  - " << n << "\n";
  written_.push_back(f.name);
}

void Writer::write_manifest(const std::string& header) const {
  write_text(out_ / "figures.md", header + manifest_.str());
}

}  // namespace capflow::figures
