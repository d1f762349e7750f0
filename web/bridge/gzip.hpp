// gzip (RFC 1952) of an HTTP answer's body, for browsers that accept it: a
// recording's 8 s window is 1.6 MB of JSON and about a sixth of that in
// gzip, which matters over a real network (docs/game.md, Replays).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace groundsim::web {

// Whether an Accept-Encoding header value admits gzip ("gzip", "gzip;q=0.5",
// "*"; not "gzip;q=0").
bool acceptsGzip(std::string_view accept_encoding);

// The gzip of `body` at zlib's fastest level (it runs on the request's
// thread, per answer), or nullopt if zlib fails.
std::optional<std::string> gzip(std::string_view body);

}  // namespace groundsim::web
