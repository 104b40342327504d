// capflow/app/run_log: what a run tells its user - log lines (stderr and run.log) and events
// (events.jsonl, one JSON object per line with "event", "wall_time" (UTC) and "t").
//
// Console lines go through app/console.h (made printable; a console that is gone - a closed pipe,
// a hung-up terminal - is noted once in run.log and the run goes on).
// A write that fails throws OutputError (from RunDirectory's files). After that the log is
// degraded: say() still prints to stderr, files are no longer written and nothing throws, so
// the failure can be reported and the run closed. Safe to call from the renderer thread too.
#pragma once

#include <mutex>
#include <string>

#include "app/run_directory.h"
#include "control/record.h"

namespace capflow::app {

class RunLog {
 public:
  RunLog(RunDirectory& dir, bool tty) : dir_(dir), tty_(tty) {}

  void say(const std::string& line);
  // `e` gets "wall_time" and "t".
  void event(control::Record e, double t);
  // The progress line: rewritten in place on a terminal, a log line otherwise.
  void status(const std::string& line);
  // Stop writing files (after an output failure): stderr only, never throws.
  void degrade() {
    std::lock_guard<std::mutex> l(mu_);
    degraded_ = true;
  }
  bool tty() const { return tty_; }

 private:
  void note_console_gone();  // once, in run.log, when the console went away
  RunDirectory& dir_;
  bool tty_;
  bool console_gone_noted_ = false;
  bool degraded_ = false;
  std::mutex mu_;
};

// The current UTC time, ISO 8601 ("2026-12-04T15:26:49Z").
std::string iso_now();

}  // namespace capflow::app
