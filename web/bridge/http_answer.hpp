// Answers computed off the I/O thread (recordings.hpp; HttpAnswer itself is
// protocol/http_answer.hpp, and every answer here says its content type:
// JSON), and the pieces of a request's query its answers read: parameters, seconds,
// metres, each refused with a reason naming the parameter.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "protocol/http_answer.hpp"

namespace groundsim::web {

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
