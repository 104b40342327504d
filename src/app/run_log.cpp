#include "app/run_log.h"

#include <ctime>
#include <iostream>

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
  if (tty_) std::cerr << "\r\033[K";
  std::cerr << line << std::endl;
  if (!degraded_) dir_.log().append("[" + iso_now() + "] " + line + "\n");
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
  std::cerr << "\r\033[K" << line << std::flush;
}

}  // namespace capflow::app
