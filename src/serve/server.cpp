#include "serve/server.h"

#include <httplib.h>

#include <cctype>
#include <stdexcept>

namespace capflow::serve {

namespace {

constexpr size_t kMaxHeaders = 64;
constexpr int kWorkers = 8;

Request to_request(const httplib::Request& h) {
  Request r;
  r.method = h.method;
  r.path = h.path;
  for (const auto& [k, v] : h.params) r.params.emplace(k, v);  // the first of each name stays
  for (const auto& [k, v] : h.headers) {
    std::string name = k;
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    r.headers.emplace(name, v);
  }
  r.body = h.body;
  return r;
}

}  // namespace

bool parse_serve_address(const std::string& text, ServeAddress* out, std::string* error) {
  ServeAddress a;
  std::string port = text;
  const size_t colon = text.rfind(':');
  if (colon != std::string::npos) {
    a.host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (a.host.empty() || a.host.size() > 253) {
      *error = "--serve: the address before ':' must be a host name or an IPv4 address";
      return false;
    }
    for (char c : a.host)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-')) {
        *error = "--serve: the address \"" + a.host + "\" must be a host name or an IPv4 address";
        return false;
      }
  }
  if (port.empty() || port.size() > 5 ||
      port.find_first_not_of("0123456789") != std::string::npos || std::stol(port) > 65535) {
    *error = "--serve: PORT must be a whole number in [0, 65535] (0: a free port), got \"" +
             port.substr(0, 20) + "\"";
    return false;
  }
  a.port = static_cast<int>(std::stol(port));
  *out = a;
  return true;
}

HttpServer::HttpServer(Api& api, const ServeAddress& address) : api_(api), address_(address) {
  server_ = std::make_unique<httplib::Server>();
  httplib::Server& s = *server_;
  s.new_task_queue = [] { return new httplib::ThreadPool(kWorkers); };
  s.set_read_timeout(5, 0);
  s.set_write_timeout(5, 0);
  // One request per connection: a browser's kept-alive connections never hold the workers.
  s.set_keep_alive_max_count(1);
  s.set_payload_max_length(Api::kMaxBody);
  s.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
    if (req.headers.size() <= kMaxHeaders) return httplib::Server::HandlerResponse::Unhandled;
    res.status = 431;
    res.set_content("{\"error\":\"too many headers\"}", "application/json");
    return httplib::Server::HandlerResponse::Handled;
  });
  auto handler = [this](const httplib::Request& req, httplib::Response& res) {
    const Response out = api_.handle(to_request(req));
    res.status = out.status;
    for (const auto& [k, v] : out.headers) res.set_header(k, v);
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_content(out.body, out.content_type);
  };
  s.Get(".*", handler);
  s.Post(".*", handler);
  s.Put(".*", handler);
  s.Delete(".*", handler);
  s.Options(".*", handler);
  s.Patch(".*", handler);
  if (address_.port == 0) {
    port_ = s.bind_to_any_port(address_.host);
  } else {
    port_ = s.bind_to_port(address_.host, address_.port) ? address_.port : -1;
  }
  if (port_ <= 0)
    throw std::runtime_error("--serve: cannot listen on " + address_.host + ":" +
                             std::to_string(address_.port) +
                             " (in use, or not an address of this machine)");
  thread_ = std::thread([this] { server_->listen_after_bind(); });
}

HttpServer::~HttpServer() { stop(); }

void HttpServer::stop() {
  if (server_) server_->stop();
  if (thread_.joinable()) thread_.join();
}

std::string HttpServer::url(const std::string& token) const {
  const std::string host = address_.host == "0.0.0.0" ? "127.0.0.1" : address_.host;
  return "http://" + host + ":" + std::to_string(port_) + "/?token=" + token;
}

}  // namespace capflow::serve
