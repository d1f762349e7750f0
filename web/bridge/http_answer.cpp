#include "bridge/http_answer.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "bridge/state_json.hpp"

namespace groundsim::web {
namespace {

std::string decode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') out += ' ';
    else if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
             std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out += static_cast<char>(std::strtol(s.substr(i + 1, 2).c_str(), nullptr, 16));
      i += 2;
    } else out += s[i];
  }
  return out;
}

}  // namespace

HttpAnswer errorAnswer(int status, const std::string& why) {
  return {status, "application/json", "{\"error\":" + web::quoted(why) + "}\n"};
}

Query parseQuery(const std::string& q) {
  Query out;
  std::size_t at = 0;
  while (at <= q.size() && out.size() < 16) {
    const std::size_t amp = q.find('&', at);
    const std::string part = q.substr(at, amp == std::string::npos ? std::string::npos : amp - at);
    const std::size_t eq = part.find('=');
    if (!part.empty()) out[decode(part.substr(0, eq))] = eq == std::string::npos ? "" : decode(part.substr(eq + 1));
    if (amp == std::string::npos) break;
    at = amp + 1;
  }
  return out;
}

// A number of seconds: finite, within a day of simulated time squared away
// from overflow when turned into nanoseconds.
std::optional<double> seconds(const Query& q, const char* key, std::string& why) {
  auto it = q.find(key);
  if (it == q.end()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end || !std::isfinite(v) || v < 0 || v > 1e9) {
    why = std::string(key) + ": must be a number of seconds in [0, 1e9], got " + web::quoted(it->second.substr(0, 40));
    return std::nullopt;
  }
  return v;
}

// A coordinate in metres: finite and within the scenario layer's world.
std::optional<double> metres(const Query& q, const char* key, std::string& why) {
  auto it = q.find(key);
  if (it == q.end()) {
    why = std::string(key) + ": required, a coordinate in metres";
    return std::nullopt;
  }
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end || !std::isfinite(v) || std::abs(v) > 1e7) {
    why = std::string(key) + ": must be a number of metres in [-1e7, 1e7], got " + web::quoted(it->second.substr(0, 40));
    return std::nullopt;
  }
  return v;
}

}  // namespace groundsim::web
