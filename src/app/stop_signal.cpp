#include "app/stop_signal.h"

#include <csignal>

namespace capflow::app {

namespace {

std::atomic<bool> g_stop{false};

extern "C" void capflow_app_on_stop_signal(int sig) {
  if (g_stop.load()) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);  // second signal: exit at once
    return;
  }
  g_stop.store(true);
}

}  // namespace

const std::atomic<bool>* install_stop_signals() {
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGINT, capflow_app_on_stop_signal);
  std::signal(SIGTERM, capflow_app_on_stop_signal);
  std::signal(SIGHUP, capflow_app_on_stop_signal);
  return &g_stop;
}

}  // namespace capflow::app
