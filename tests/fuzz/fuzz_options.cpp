// libFuzzer target for the command lines of render, figure and sweep (app/render_args.h,
// app/figure_args.h, app/sweep_args.h): the input, split at NUL bytes, is one command line; it is
// parsed by CLI11 with the commands' own options, then checked as the command checks it before
// it does anything. Every input ends in options that passed every check (then the renderer's
// options are valid and finite: RenderOptions::IsValid), a CLI::ParseError or a UserError naming
// an option; anything else is a bug. Built by scripts/fuzz; replayed over
// tests/fuzz/corpus_options by CTest.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "app/errors.h"
#include "app/figure_args.h"
#include "app/render_args.h"
#include "app/sweep_args.h"

using namespace capflow::app;

namespace {

void must_be_valid(const capflow::render::RenderOptions& o, const char* who) {
  std::string err;
  const bool finite = std::isfinite(o.camera.fov_deg) && std::isfinite(o.range_min) &&
                      std::isfinite(o.range_max) && std::isfinite(o.camera.eye[0]) &&
                      std::isfinite(o.camera.eye[1]) && std::isfinite(o.camera.eye[2]);
  if (!o.IsValid(&err) || !finite) {
    std::fprintf(stderr, "%s: options passed the checks but are not valid: %s\n", who,
                 err.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 4096) return 0;
  std::vector<std::string> args = {"capflow"};
  std::string cur;
  for (size_t i = 0; i < size; ++i) {
    if (data[i] == 0) {
      args.push_back(cur);
      cur.clear();
    } else {
      cur += static_cast<char>(data[i]);
    }
  }
  if (!cur.empty()) args.push_back(cur);
  if (args.size() > 64) return 0;

  CLI::App app{"fuzz"};
  app.require_subcommand(1);
  RenderArgs render;
  FigureArgs figure;
  SweepArgs sweep;
  CLI::App* r = app.add_subcommand("render", "");
  add_render_args(r, &render);
  CLI::App* f = app.add_subcommand("figure", "");
  add_figure_args(f, &figure);
  CLI::App* s = app.add_subcommand("sweep", "");
  add_sweep_args(s, &sweep);
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), const_cast<char**>(argv.data()));
  } catch (const CLI::ParseError&) {
    return 0;
  }
  try {
    if (r->parsed()) {
      note_given(r, &render);
      must_be_valid(check_render_args(render), "render");
    }
    if (f->parsed()) {
      must_be_valid(check_figure_args(figure), "figure");
      check_labels(figure);
    }
    if (s->parsed()) check_sweep_args(sweep, 1);
  } catch (const UserError& e) {
    if (std::string(e.what()).empty()) std::abort();
  }
  return 0;
}
