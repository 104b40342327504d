#include "control/run_events.h"

#include <sstream>
#include <nlohmann/json.hpp>

#include "files/input_file.h"

namespace capflow::control {

RunEnd last_run_end(const std::string& events_path) {
  RunEnd end;
  std::istringstream in;
  try {
    in.str(files::read_input_file(events_path, "event log", kMaxEventLogBytes));
  } catch (const files::InputError&) {
    return end;  // no readable log: no end found
  }
  for (std::string line; std::getline(in, line);) {
    const nlohmann::json e = nlohmann::json::parse(line, nullptr, false);
    if (!e.is_object() || e.value("event", "") != "end") continue;
    RunEnd r;
    r.found = true;
    r.reason = e.value("reason", "");
    r.exit_code = e.value("exit_code", 0);
    const auto num = [&](const char* k) {
      const auto it = e.find(k);
      return it != e.end() && it->is_number() ? it->get<double>() : 0.0;
    };
    r.t = num("t");
    r.D = num("D");
    r.L = num("L");
    r.S = num("S");
    r.W = num("W");
    r.steps = static_cast<long>(num("steps"));
    end = r;
  }
  return end;
}

EventLine read_event_line(const std::string& line) {
  const nlohmann::json e = nlohmann::json::parse(line, nullptr, false);
  EventLine r;
  if (!e.is_object()) return r;
  const auto text = [&](const char* k) {
    const auto it = e.find(k);
    return it != e.end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  r.event = text("event");
  r.reason = text("reason");
  if (const auto it = e.find("exit_code"); it != e.end() && it->is_number_integer())
    r.exit_code = it->get<int>();
  return r;
}

}  // namespace capflow::control
