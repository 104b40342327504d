// capflow/app/stop_signal: SIGINT, SIGTERM and SIGHUP ask a long command (capflow run, capflow
// steady) to stop cleanly; a second signal ends the process at once. SIGXFSZ is ignored, so that
// a file-size limit shows as a failed write (exit 5) instead of killing the process.
#pragma once

#include <atomic>

namespace capflow::app {

// Installs the handlers; returns the flag the first signal sets.
const std::atomic<bool>* install_stop_signals();

}  // namespace capflow::app
