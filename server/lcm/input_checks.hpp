// What the LCM server's input handlers (lcm_server_input.cpp, and the
// resend handler in lcm_server.cpp) check of a datagram before the session
// service sees it: the decode status as an error code, and ids and tokens
// short and printable.
#pragma once

#include <string>
#include <utility>

#include "protocol/codec.hpp"
#include "protocol/limits.hpp"
#include "protocol/text.hpp"
#include "session/types.hpp"

namespace groundsim::net::input_checks {

inline session::ErrorCode codeFor(DecodeStatus s) {
  return s == DecodeStatus::Fingerprint ? session::ErrorCode::Fingerprint : session::ErrorCode::Decode;
}

// Ids and tokens are echoed in replies, events and logs: they must be short
// and printable. "" when fine, else the reason naming the field.
inline std::string badId(const char* field, const std::string& v) {
  bool printable = true;
  for (unsigned char c : v) printable = printable && c >= 0x20 && c != 0x7f;
  if (v.size() <= kMaxIdBytes && printable) return "";
  return std::string(field) + ": " + net::quoted(v) + (printable ? "" : " holds control characters") +
         (v.size() > kMaxIdBytes ? ", longer than " + std::to_string(kMaxIdBytes) + " bytes" : "");
}

// The first of a car input's ids (client_id, session_id, token) that is
// not a valid id, and why; empty when all three are.
template <class Msg>
std::string badIds(const Msg& msg) {
  for (const auto& [field, v] : {std::pair{"client_id", &msg.client_id}, std::pair{"session_id", &msg.session_id},
                                 std::pair{"token", &msg.token}})
    if (std::string why = badId(field, *v); !why.empty()) return why;
  return {};
}

}  // namespace groundsim::net::input_checks
