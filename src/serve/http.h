// capflow/serve/http: a request and a response as plain data. The HTTP library (serve/server.h)
// fills a Request and sends the Response; the API (serve/api.h) maps one to the other without a
// socket, so that tests and the fuzzer drive it directly.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace capflow::serve {

struct Request {
  std::string method;  // "GET", "POST", ...
  std::string path;    // decoded, without the query
  std::map<std::string, std::string> params;   // query parameters (the first of each name)
  std::map<std::string, std::string> headers;  // names in lower case
  std::string body;

  std::string param(const std::string& k) const {
    const auto it = params.find(k);
    return it == params.end() ? "" : it->second;
  }
  bool has_param(const std::string& k) const { return params.count(k) > 0; }
  std::string header(const std::string& k) const {
    const auto it = headers.find(k);
    return it == headers.end() ? "" : it->second;
  }
};

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // extra headers
};

}  // namespace capflow::serve
