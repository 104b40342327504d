// libFuzzer target for the control-file parser, validator, edit policy and schedule engine.
// Built by scripts/fuzz (clang, -fsanitize=fuzzer,address,undefined). Invariants checked:
//  * parse_control never crashes: it returns options or throws ControlError (anything else is a
//    bug and aborts);
//  * a valid document round-trips: parse(to_json_text(o)) is valid and prints the same text;
//  * applying an identical edit changes nothing;
//  * the schedule engine yields finite Ca in (0, 100] over a sampled run.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "control/control_file.h"
#include "control/edit.h"
#include "control/schedule.h"

using namespace capflow::control;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ParsedControl p;
  try {
    p = parse_control(text, "fuzz");
  } catch (const ControlError&) {
    return 0;
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
  CaScheduler s(p.options.ca, p.options.steady, 0.0);
  double t = 0;
  for (int k = 0; k < 200; ++k) {
    t += 0.05;
    const double ca = s.ca(t);
    if (!(std::isfinite(ca) && ca > 0 && ca <= 100)) {
      std::fprintf(stderr, "schedule produced Ca = %g at t = %g\n", ca, t);
      std::abort();
    }
    s.sample(t, 1.0 + 0.1 * std::exp(-t), 1.0, 1.0);
  }
  return 0;
}
