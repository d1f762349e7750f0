#include "bridge/gzip.hpp"

#include <cctype>
#include <cstdlib>

#include <zlib.h>

namespace groundsim::web {

bool acceptsGzip(std::string_view h) {
  std::size_t at = 0;
  while (at < h.size()) {
    std::size_t comma = h.find(',', at);
    if (comma == std::string_view::npos) comma = h.size();
    std::string_view item = h.substr(at, comma - at);
    at = comma + 1;
    while (!item.empty() && std::isspace(static_cast<unsigned char>(item.front()))) item.remove_prefix(1);
    const std::size_t semi = item.find(';');
    std::string_view coding = item.substr(0, semi);
    while (!coding.empty() && std::isspace(static_cast<unsigned char>(coding.back()))) coding.remove_suffix(1);
    if (coding != "gzip" && coding != "*") continue;
    if (semi == std::string_view::npos) return true;
    const std::size_t q = item.find("q=", semi);
    if (q == std::string_view::npos) return true;
    const std::string value(item.substr(q + 2, 8));
    if (std::strtod(value.c_str(), nullptr) > 0.0) return true;
  }
  return false;
}

std::optional<std::string> gzip(std::string_view body) {
  z_stream z{};
  // windowBits 15 + 16: a gzip wrapper, not zlib's
  if (deflateInit2(&z, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) return std::nullopt;
  std::string out(deflateBound(&z, static_cast<uLong>(body.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(body.data()));
  z.avail_in = static_cast<uInt>(body.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&z, Z_FINISH);
  const std::size_t n = out.size() - z.avail_out;
  deflateEnd(&z);
  if (rc != Z_STREAM_END) return std::nullopt;
  out.resize(n);
  return out;
}

}  // namespace groundsim::web
