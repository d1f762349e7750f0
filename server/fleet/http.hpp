// HTTP/1.1 POST with a deadline over Boost.Beast, for the etcd client: one
// connection per request (Connection: close), every step bounded by the
// deadline. Internal to server/fleet.
#pragma once

#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>

namespace groundsim::fleet {

struct Url {
  std::string host, port;
};
// "http://host:port", "host:port", "http://[::1]:2379"; throws std::invalid_argument (https: no TLS here).
Url parseUrl(const std::string& url);

struct HttpAnswer {
  unsigned status = 0;
  std::string body;
};

// No answer: connection refused, timeout, closed. what() is the reason.
struct HttpFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

HttpAnswer httpPost(const Url& url, const std::string& target, const std::string& body,
                    std::chrono::milliseconds timeout);

// A POST whose answer is a stream (etcd's /v3/watch): on_bytes gets each
// piece of the body as it arrives and returns false to end the stream.
// connect_timeout bounds the connection and the request; the stream itself
// may then last, checked every poll: keep_going() false ends it. Returns the
// HTTP status; throws HttpFailure when no answer came or the stream broke.
unsigned httpPostStream(const Url& url, const std::string& target, const std::string& body,
                        std::chrono::milliseconds connect_timeout, std::chrono::milliseconds poll,
                        const std::function<bool(const std::string&)>& on_bytes,
                        const std::function<bool()>& keep_going);

}  // namespace groundsim::fleet
