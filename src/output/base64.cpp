// capflow/output/base64: Base64 (RFC 4648), the binary encoding of the ParaView arrays.
#include <cctype>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "files/printable.h"
#include "output/vtk.h"

namespace capflow::output {

std::string base64_encode(const void* data, size_t bytes) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string o;
  o.reserve((bytes + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes; i += 3) {
    const uint32_t v = (p[i] << 16) | (p[i + 1] << 8) | p[i + 2];
    o += tbl[v >> 18];
    o += tbl[(v >> 12) & 63];
    o += tbl[(v >> 6) & 63];
    o += tbl[v & 63];
  }
  if (i < bytes) {
    const uint32_t v = (p[i] << 16) | (i + 1 < bytes ? p[i + 1] << 8 : 0);
    o += tbl[v >> 18];
    o += tbl[(v >> 12) & 63];
    o += i + 1 < bytes ? tbl[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

std::vector<unsigned char> base64_decode(const std::string& text) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  out.reserve(text.size() * 3 / 4);
  uint32_t acc = 0;
  int bits = 0;
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (c == '=') {
      // Padding ends a group; VTK may start a new base64 block right after it.
      acc = 0;
      bits = 0;
      continue;
    }
    const int v = val(c);
    if (v < 0)
      throw std::runtime_error("base64: invalid character '" +
                               files::printable(std::string_view(&c, 1)) + "'");
    acc = (acc << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((acc >> bits) & 0xFF));
    }
  }
  return out;
}

}  // namespace capflow::output
