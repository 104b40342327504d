// capflow/app/control_feed: see control_feed.h.
#include "app/control_feed.h"

#include <chrono>
#include <memory>

#include "control/watcher.h"

namespace capflow::app {

namespace {
constexpr auto kPoll = std::chrono::milliseconds(100);
}

ControlFeed::ControlFeed(std::string path, const std::atomic<bool>* signal, bool check_now)
    : path_(std::move(path)), signal_(signal) {
  std::unique_ptr<control::FileWatcher> watcher;
  if (!path_.empty()) {
    watcher = std::make_unique<control::FileWatcher>(path_);
    inotify_ = watcher->using_inotify();
    if (check_now) saved_.push_back(read());
  }
  thread_ = std::thread([this, w = std::move(watcher)]() mutable {
    while (!quit_.load()) {
      if (signal_ && signal_->load()) stop_.store(true);
      if (w && w->changed()) {
        Saved s = read();
        if (s.run_keys && s.run_keys->state == control::RunState::Stopped) stop_.store(true);
        std::lock_guard<std::mutex> lock(mutex_);
        saved_.push_back(std::move(s));
      }
      std::this_thread::sleep_for(kPoll);
    }
  });
}

ControlFeed::~ControlFeed() {
  quit_.store(true);
  if (thread_.joinable()) thread_.join();
}

ControlFeed::Saved ControlFeed::read() const {
  Saved s;
  std::string text;
  try {
    text = control::read_control_text(path_);
    s.parsed = control::parse_control(text, path_);
    s.run_keys = s.parsed->options.run;
  } catch (const control::ControlError& e) {
    s.issues = e.issues();
    const std::string what = e.what();
    s.error = what.substr(what.find('\n') + 1);
    // a stop or a pause saved with a value the edit refuses is honoured all the same
    s.run_keys = control::run_keys_of(text);
  }
  return s;
}

std::optional<ControlFeed::Saved> ControlFeed::take() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (saved_.empty()) return std::nullopt;
  Saved s = std::move(saved_.front());
  saved_.pop_front();
  return s;
}

}  // namespace capflow::app
