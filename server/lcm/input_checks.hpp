// What the LCM server's input handlers (lcm_server_input.cpp, and the
// resend handler in lcm_server.cpp) check of a datagram before the session
// service sees it: the decode status as an error code, and ids and tokens
// short and printable.
#pragma once

#include <string>

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

}  // namespace groundsim::net::input_checks
