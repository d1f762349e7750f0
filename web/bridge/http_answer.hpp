// An HTTP answer computed off the I/O thread (recordings.hpp), and the
// pieces of a request's query its answers read: parameters, seconds,
// metres, each refused with a reason naming the parameter.
#pragma once

#include <map>
#include <optional>
#include <string>

namespace groundsim::web {

struct HttpAnswer {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
};

// {"error":"why"} with that status.
HttpAnswer errorAnswer(int status, const std::string& why);

// A query (without the '?'), its names and values percent-decoded; at most 16 parameters.
using Query = std::map<std::string, std::string>;
Query parseQuery(const std::string& q);

// A number of seconds in [0, 1e9]; nothing if the key is absent, or if it
// is not such a number (then `why` says so).
std::optional<double> seconds(const Query& q, const char* key, std::string& why);
// A coordinate in metres in [-1e7, 1e7], required (else `why` says so).
std::optional<double> metres(const Query& q, const char* key, std::string& why);

}  // namespace groundsim::web
