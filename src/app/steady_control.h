// capflow/app/steady_control: the live control file of `capflow steady`.
//
// A Newton solve takes seconds to minutes and cannot look at the file itself, so a thread
// watches it (control::FileWatcher, every 0.1 s): each saved version is read and validated
// there, and
//   * "run": {"state": "stopped"} (or a stop signal) sets stop() at once: the solvers check it
//     at every velocity evaluation, the branch ends, the states found are kept - also when the
//     rest of the saved file is refused (control::run_keys_of);
//   * everything else waits in take() for the solver thread, which applies it between states
//     and approach steps (app/steady_run.cpp: the target range, the tolerances, a pause).
#pragma once

#include <atomic>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "control/control_file.h"

namespace capflow::app {

class SteadyControl {
 public:
  // `path`: the control file ("" = none: only the signal is relayed). `signal`: set by the
  // signal handler (may be null).
  SteadyControl(std::string path, const std::atomic<bool>* signal);
  ~SteadyControl();
  SteadyControl(const SteadyControl&) = delete;
  SteadyControl& operator=(const SteadyControl&) = delete;

  const std::atomic<bool>* stop() const { return &stop_; }
  bool stopping() const { return stop_.load(); }

  // A saved version of the file: parsed, or refused (error: the validation's message).
  struct Saved {
    std::optional<control::ParsedControl> parsed;
    std::string error;
  };
  // The oldest saved version the solver has not taken yet.
  std::optional<Saved> take();

 private:
  void watch();

  std::string path_;
  const std::atomic<bool>* signal_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> quit_{false};
  std::mutex mutex_;
  std::deque<Saved> saved_;
  std::thread thread_;
};

}  // namespace capflow::app
