#include "scenario/object_reader.hpp"
#include "text.hpp"

#include <cstdio>

namespace groundsim::net {
namespace {

void escapeInto(std::string& out, std::string_view s, std::size_t max, bool quotes) {
  const std::size_t n = s.size() < max ? s.size() : max;
  out.reserve(out.size() + n + 16);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '\\') out += "\\\\";
    else if (c == '"' && quotes) out += "\\\"";
    else if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);  // UTF-8 bytes pass (a cut may split one: still no control byte)
    }
  }
  if (quotes) out += '"';
  if (s.size() > max) out += "... (" + std::to_string(s.size()) + " bytes)";
}

}  // namespace

std::string quoted(std::string_view s, std::size_t max) {
  std::string out = "\"";
  escapeInto(out, s, max, true);
  return out;
}

std::string printable(std::string_view s, std::size_t max) {
  std::string out;
  escapeInto(out, s, max, false);
  return out;
}

std::string number(double x) { return scenario::formatNumber(x); }

}  // namespace groundsim::net
