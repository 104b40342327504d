// capflow/figures/writer: writes figures into the output directory and lists them in
// figures.md (the captions, sources and notes: what was made from what).
//
// Each 2-D figure becomes <name>.dat and <name>.gp; with gnuplot on the PATH the script is run
// and makes <name>.svg or .pdf and <name>.png. A gnuplot failure is noted (its log kept as
// <name>.gnuplot.log) and counted, not thrown: the other figures are still made.
#pragma once

#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "figures/figure.h"

namespace capflow::figures {

bool gnuplot_on_path();

// The largest magnitude a figure draws: beyond it gnuplot's axis ranges overflow (emit() leaves
// such values out, and non-finite ones, with a note in figures.md).
constexpr double kMaxPlotValue = 1e300;

class Writer {
 public:
  using Say = std::function<void(const std::string& line)>;
  // vector_format "svg" or "pdf"; png: a PNG beside it; run_gnuplot: make the images; say: where
  // the progress lines and notes go (the caller's console).
  Writer(std::filesystem::path out, std::string vector_format, bool png, bool run_gnuplot,
         Say say);

  const std::filesystem::path& out() const { return out_; }
  bool runs_gnuplot() const { return gnuplot_; }

  void note(const std::string& message);  // to the console and figures.md
  void say(const std::string& line) const { say_(line); }  // to the console only
  void emit(const Figure& fig);           // skipped (with a note) when no series has data
  // A figure made elsewhere (a 3-D view): its figures.md entry, counted as written.
  void record(const std::string& name, const std::string& entry);

  int failures() const { return failures_; }
  const std::vector<std::string>& written() const { return written_; }
  // figures.md: the header, then the entries and notes in the order they came.
  void write_manifest(const std::string& header) const;

 private:
  bool run_script(const Figure& f);

  std::filesystem::path out_;
  std::string vector_;
  Say say_;
  bool png_ = true, gnuplot_ = false;
  int failures_ = 0;
  std::ostringstream manifest_;
  std::vector<std::string> written_;
};

// Replaces p atomically (files/atomic_write.h); files::WriteError naming p on failure.
void write_text(const std::filesystem::path& p, const std::string& text);

}  // namespace capflow::figures
