#include "app/run_log.h"

#include <ctime>

#include "app/console.h"

namespace capflow::app {

std::string iso_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

void RunLog::say(const std::string& line) {
  std::lock_guard<std::mutex> l(mu_);
  if (tty_ && !console::err_gone()) console::status("");
  console::err(line);
  if (degraded_) return;
  dir_.log().append("[" + iso_now() + "] " + line + "\n");
  note_console_gone();
}

void RunLog::note_console_gone() {
  if (console_gone_noted_ || !console::err_gone()) return;
  console_gone_noted_ = true;
  dir_.log().append("[" + iso_now() + "] the console is gone (stderr: " +
                    console::err_gone_reason() +
                    "): the run goes on, and this log and events.jsonl are its record\n");
}

void RunLog::event(control::Record e, double t) {
  std::lock_guard<std::mutex> l(mu_);
  if (degraded_) return;
  e.set("wall_time", iso_now()).set("t", t);
  dir_.events().append(e.text() + "\n");
}

void RunLog::status(const std::string& line) {
  if (!tty_) return say(line);
  std::lock_guard<std::mutex> l(mu_);
  console::status(line);
  if (!degraded_) note_console_gone();
}

}  // namespace capflow::app
