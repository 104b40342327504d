#include "app/stop_signal.h"

#include <csignal>

namespace capflow::app {

namespace {

std::atomic<bool> g_stop{false};

extern "C" void capflow_app_on_stop_signal(int sig) {
  // A hang-up comes more than once when a terminal closes (the shell passes it on, the kernel
  // sends it to the foreground group): it never ends the process at once, only asks it to stop.
  if (g_stop.load() && sig != SIGHUP) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);  // second SIGINT or SIGTERM: exit at once
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
