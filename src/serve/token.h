// capflow/serve/token: the live console's access token (Jupyter-style: printed once in the URL).
//
// new_token(): 32 hex digits (128 bits) from the kernel's random source (getrandom).
// same_token(): compares in time independent of where the strings differ (no early exit), so
// that response times do not reveal a prefix of the token.
// token_of(): the token a request carries - "Authorization: Bearer T", the header
// "X-Capflow-Token: T", the query parameter token=T or the cookie capflow_token=T - and whether
// it came in a header (POSTs must: a cookie alone is what a cross-site request would carry).
#pragma once

#include <string>

#include "serve/http.h"

namespace capflow::serve {

std::string new_token();
bool same_token(const std::string& given, const std::string& expected);

struct GivenToken {
  std::string value;
  bool in_header = false;  // Authorization: Bearer or X-Capflow-Token
};
GivenToken token_of(const Request& r);

}  // namespace capflow::serve
