// capflow/app/live_console: --serve [ADDR:]PORT and --serve-linger SECONDS of capflow run, steady
// and view: the live console's server (serve/server.h) over a source (app/console_source.h).
//
// At start it prints one line, "capflow: console at http://127.0.0.1:PORT/?token=TOKEN" (PORT 0:
// the free port chosen), on stderr and in the run's log. It binds to 127.0.0.1 unless given an
// address; another address prints a warning (the token still guards it). ssh -L PORT:localhost:
// PORT NODE reaches it from a laptop. When the run ends the page shows its final state; with a
// linger the server stays up that long afterwards (a signal ends the wait).
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "serve/source.h"

namespace CLI {
class App;
}

namespace capflow::serve {
class Api;
class FrameService;
class HttpServer;
}  // namespace capflow::serve

namespace capflow::app {

struct ServeOptions {
  std::string address;  // "" = no console
  double linger = 0;    // seconds the server stays after the run
  bool enabled() const { return !address.empty(); }
};

// --serve and --serve-linger on `c` (their values checked: UserError-style messages, exit 2).
void add_serve_options(CLI::App* c, ServeOptions* o, bool linger = true);

class LiveConsole {
 public:
  // UserError when the address does not parse or cannot be bound.
  LiveConsole(serve::Source& source, const ServeOptions& o);
  ~LiveConsole();
  const std::string& url() const { return url_; }
  // Keeps serving for the linger time (or until `stop` is set), then stops.
  void linger(const std::atomic<bool>* stop);

 private:
  ServeOptions opt_;
  std::string url_;
  std::unique_ptr<serve::FrameService> frames_;
  std::unique_ptr<serve::Api> api_;
  std::unique_ptr<serve::HttpServer> server_;
};

}  // namespace capflow::app
