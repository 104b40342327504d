// capflow/serve/server: the live console's HTTP server (cpp-httplib, Debian's libcpp-httplib-dev)
// on threads of its own, beside the solver and the renderer: it reads what the run publishes
// (serve/source.h, the run directory) and never holds a lock the solver waits for.
//
// Limits: 8 worker threads (further connections wait for one); one request per connection (a
// browser's kept-alive connections, polled every 250 ms, would otherwise hold the workers for
// good); a request line and each header at most 8 KiB (the library's), at most 64 headers, a
// body at most Api::kMaxBody; reads and writes time out after 5 s, so a slow or stalled client
// holds one worker for seconds at most.
#pragma once

#include <memory>
#include <string>
#include <thread>

#include "serve/api.h"

namespace httplib {
class Server;
}

namespace capflow::serve {

struct ServeAddress {
  std::string host = "127.0.0.1";
  int port = 0;  // 0: a free port
  bool local() const { return host == "127.0.0.1" || host == "localhost" || host == "::1"; }
};

// "[ADDR:]PORT" (PORT in [0, 65535]; ADDR an IPv4 address or a host name): false and *error
// naming what is wrong.
bool parse_serve_address(const std::string& text, ServeAddress* out, std::string* error);

class HttpServer {
 public:
  // Binds and starts serving; std::runtime_error naming the address when it cannot bind.
  HttpServer(Api& api, const ServeAddress& address);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }
  // http://HOST:PORT/?token=TOKEN
  std::string url(const std::string& token) const;
  void stop();

 private:
  Api& api_;
  ServeAddress address_;
  int port_ = 0;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
};

}  // namespace capflow::serve
