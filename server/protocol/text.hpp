// User strings in messages: whatever a client sends (names, ids, scenario
// text) is quoted, escaped and cut before it is printed or echoed, so that a
// 50 MB name stays one short line and a NUL or an escape sequence never
// reaches a terminal raw.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace groundsim::net {

inline constexpr std::size_t kMaxEcho = 200;  // characters of a user string in a message

// "text" with \", \\, \n, \t and \xNN escapes, cut to max characters of the
// input (then "... (N bytes)").
std::string quoted(std::string_view s, std::size_t max = kMaxEcho);
// The same escaping without the quotes, for text shown as it is (a server's
// error message, a scenario name in a table).
std::string printable(std::string_view s, std::size_t max = kMaxEcho);
// A number as a short readable text (%g): DBL_MAX is "1.79769e+308", not 309
// digits (scenario::formatNumber, the one formatter).
std::string number(double x);

}  // namespace groundsim::net
