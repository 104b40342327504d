// capflow/app/control_feed: the live control file of a running command.
//
// A thread watches the file (control::FileWatcher, every 0.1 s) and reads and validates each
// saved version there, so that a solver that runs for minutes between step boundaries (a Newton
// solve of capflow steady) can still be stopped:
//   * a stop - a signal, or "run": {"state": "stopped"} saved (also in a version refused
//     otherwise: control::run_keys_of) - sets stop() at once; the solvers check it at every
//     velocity evaluation;
//   * every saved version waits in take() for the driver, which applies it at its next step
//     boundary (app/edit_report.h).
// With check_now, the version on disk is taken as saved at the start (a resumed run applies
// what was edited while it was stopped).
#pragma once

#include <atomic>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "control/control_file.h"

namespace capflow::app {

class ControlFeed {
 public:
  // `path`: the control file ("" = none: only the signal is relayed). `signal`: set by the
  // signal handler (may be null).
  ControlFeed(std::string path, const std::atomic<bool>* signal, bool check_now = false);
  ~ControlFeed();
  ControlFeed(const ControlFeed&) = delete;
  ControlFeed& operator=(const ControlFeed&) = delete;

  const std::string& path() const { return path_; }
  bool watching() const { return !path_.empty(); }
  bool using_inotify() const { return inotify_; }
  // Set by a signal or a saved stop; solvers poll it.
  const std::atomic<bool>* stop() const { return &stop_; }
  bool stopping() const { return stop_.load(); }
  bool signalled() const { return signal_ && signal_->load(); }

  // A saved version of the file: parsed, or refused (its issues and message), with the run
  // keys it holds either way.
  struct Saved {
    std::optional<control::ParsedControl> parsed;
    std::vector<control::ControlIssue> issues;
    std::string error;  // the refusal's message (the issues, one per line)
    std::optional<control::RunOptions> run_keys;
  };
  // The oldest saved version the driver has not taken yet.
  std::optional<Saved> take();

 private:
  void watch();
  Saved read() const;

  std::string path_;
  const std::atomic<bool>* signal_;
  bool inotify_ = false;
  std::atomic<bool> stop_{false};
  std::atomic<bool> quit_{false};
  std::mutex mutex_;
  std::deque<Saved> saved_;
  std::thread thread_;
};

}  // namespace capflow::app
