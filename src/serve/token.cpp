#include "serve/token.h"

#include <sys/random.h>

#include <cerrno>
#include <stdexcept>

namespace capflow::serve {

std::string new_token() {
  unsigned char b[16];
  size_t got = 0;
  while (got < sizeof b) {
    const ssize_t n = getrandom(b + got, sizeof b - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error("cannot draw the console's token: getrandom failed");
    got += static_cast<size_t>(n);
  }
  static const char* const hex = "0123456789abcdef";
  std::string t;
  for (unsigned char c : b) {
    t += hex[c >> 4];
    t += hex[c & 15];
  }
  return t;
}

bool same_token(const std::string& given, const std::string& expected) {
  // Every byte of `expected` is visited whatever `given` holds; the lengths are compared last.
  unsigned char diff = 0;
  for (size_t i = 0; i < expected.size(); ++i)
    diff |= static_cast<unsigned char>(expected[i]) ^
            static_cast<unsigned char>(i < given.size() ? given[i] : 0);
  return (diff == 0) & (given.size() == expected.size()) & !expected.empty();
}

namespace {

std::string cookie_value(const std::string& cookies, const std::string& name) {
  size_t at = 0;
  while (at < cookies.size()) {
    size_t end = cookies.find(';', at);
    if (end == std::string::npos) end = cookies.size();
    std::string part = cookies.substr(at, end - at);
    const size_t first = part.find_first_not_of(' ');
    part = first == std::string::npos ? "" : part.substr(first);
    if (part.compare(0, name.size() + 1, name + "=") == 0) return part.substr(name.size() + 1);
    at = end + 1;
  }
  return "";
}

}  // namespace

GivenToken token_of(const Request& r) {
  const std::string auth = r.header("authorization");
  if (auth.compare(0, 7, "Bearer ") == 0) return {auth.substr(7), true};
  if (const std::string h = r.header("x-capflow-token"); !h.empty()) return {h, true};
  if (const std::string q = r.param("token"); !q.empty()) return {q, false};
  return {cookie_value(r.header("cookie"), "capflow_token"), false};
}

}  // namespace capflow::serve
