// capflow/app/stop_signal: SIGINT, SIGTERM and SIGHUP ask a long command (capflow run, capflow
// steady) to stop cleanly; a second SIGINT or SIGTERM ends the process at once (a repeated
// SIGHUP does not: a closing terminal sends several). SIGXFSZ is ignored, so that a file-size
// limit shows as a failed write (exit 5) instead of killing the process; SIGPIPE is ignored by
// main (app/console.h).
#pragma once

#include <atomic>

namespace capflow::app {

// Installs the handlers; returns the flag the first signal sets.
const std::atomic<bool>* install_stop_signals();

}  // namespace capflow::app
