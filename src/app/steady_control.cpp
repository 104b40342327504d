#include "app/steady_control.h"

#include <chrono>
#include <memory>

#include "control/watcher.h"

namespace capflow::app {

namespace {
constexpr auto kPoll = std::chrono::milliseconds(100);
}

SteadyControl::SteadyControl(std::string path, const std::atomic<bool>* signal)
    : path_(std::move(path)), signal_(signal) {
  thread_ = std::thread([this] { watch(); });
}

SteadyControl::~SteadyControl() {
  quit_.store(true);
  if (thread_.joinable()) thread_.join();
}

std::optional<SteadyControl::Saved> SteadyControl::take() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (saved_.empty()) return std::nullopt;
  Saved s = std::move(saved_.front());
  saved_.pop_front();
  return s;
}

void SteadyControl::watch() {
  std::unique_ptr<control::FileWatcher> watcher;
  if (!path_.empty()) watcher = std::make_unique<control::FileWatcher>(path_);
  while (!quit_.load()) {
    if (signal_ && signal_->load()) stop_.store(true);
    if (watcher && watcher->changed()) {
      Saved s;
      std::string text;
      try {
        text = control::read_control_text(path_);
        s.parsed = control::parse_control(text, path_);
        if (s.parsed->options.run.state == control::RunState::Stopped) stop_.store(true);
      } catch (const control::ControlError& e) {
        const std::string what = e.what();
        s.error = what.substr(what.find('\n') + 1);
        // a stop saved with a value the edit refuses is honoured all the same
        const std::optional<control::RunOptions> run = control::run_keys_of(text);
        if (run && run->state == control::RunState::Stopped) stop_.store(true);
      }
      std::lock_guard<std::mutex> lock(mutex_);
      saved_.push_back(std::move(s));
    }
    std::this_thread::sleep_for(kPoll);
  }
}

}  // namespace capflow::app
