#include "app/live_console.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <thread>

#include "app/console.h"
#include "app/cpu_budget.h"
#include "app/errors.h"
#include "serve/api.h"
#include "serve/frame_service.h"
#include "serve/server.h"
#include "serve/token.h"

namespace capflow::app {

void add_serve_options(CLI::App* c, ServeOptions* o, bool linger) {
  c->add_option("--serve", o->address,
                "Serve the live console at [ADDR:]PORT (127.0.0.1 unless ADDR; PORT 0: a free "
                "port); prints its URL with the access token")
      ->check([](const std::string& v) {
        serve::ServeAddress a;
        std::string error;
        return serve::parse_serve_address(v, &a, &error) ? std::string() : error;
      });
  if (linger)
    c->add_option("--serve-linger", o->linger,
                  "Keep the console up this many seconds after the run ends, in [0, 86400]")
        ->check(CLI::Range(0.0, 86400.0));
}

LiveConsole::LiveConsole(serve::Source& source, const ServeOptions& o)
    : opt_(o) {
  serve::ServeAddress address;
  std::string error;
  if (!serve::parse_serve_address(o.address, &address, &error)) throw UserError(error);
  std::map<std::string, std::string> assets;
  try {
    assets = serve::load_console_assets();
  } catch (const std::exception& e) {
    throw UserError(std::string("--serve: the console's page is missing: ") + e.what());
  }
  const std::string token = serve::new_token();
  // The frames' renderer shares the cores with the solver as the movie's does.
  render_cpu_defaults();
  frames_ = std::make_unique<serve::FrameService>(source.render_options(), renderer_busy);
  api_ = std::make_unique<serve::Api>(source, frames_.get(), token, std::move(assets));
  try {
    server_ = std::make_unique<serve::HttpServer>(*api_, address);
  } catch (const std::runtime_error& e) {
    throw UserError(e.what());
  }
  url_ = server_->url(token);
  if (!address.local())
    console::err("capflow: warning: the console listens on " + address.host +
                 ", not only on this machine; anyone who can reach it still needs the token");
  console::err("capflow: console at " + url_);
}

LiveConsole::~LiveConsole() {
  if (server_) server_->stop();
}

void LiveConsole::linger(const std::atomic<bool>* stop) {
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::milliseconds(static_cast<long>(opt_.linger * 1000));
  if (opt_.linger > 0 && opt_.linger <= 86400)
    console::err("capflow: the console stays up for " + std::to_string(opt_.linger) +
                 " s (" + url_ + ")");
  while (std::chrono::steady_clock::now() < until && !(stop && stop->load()))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (server_) server_->stop();
}

}  // namespace capflow::app
