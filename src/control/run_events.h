// capflow/control/run_events: what a run directory's events.jsonl says about how the run ended
// (the "end" event that `capflow run` appends, app/simulation.cpp), for `capflow sweep`.
// Lines that are not JSON objects (a line cut by a crash) are skipped. The file is read under
// files/input_file.h's rule (a regular file of at most kMaxEventLogBytes).
#pragma once

#include <cstddef>
#include <string>

namespace capflow::control {

constexpr std::size_t kMaxEventLogBytes = std::size_t{256} << 20;

struct RunEnd {
  bool found = false;  // an "end" event exists
  std::string reason;  // "t_end reached", "stopped by signal", "failure", ...
  int exit_code = 0;
  double t = 0, D = 0, L = 0, S = 0, W = 0;
  long steps = 0;
};

// The last "end" event of the file (found = false if there is none, or the file is missing or
// is not a readable regular file within the bound).
RunEnd last_run_end(const std::string& events_path);

// One line of events.jsonl: its "event" and "reason" ("" when absent or the line is not a JSON
// object).
struct EventLine {
  std::string event, reason;
  int exit_code = -1;  // -1: none
};
EventLine read_event_line(const std::string& line);

}  // namespace capflow::control
