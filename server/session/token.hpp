// Session ids and ownership tokens. A token is 128 bits from the kernel's
// CSPRNG (std::random_device reads /dev/urandom on Linux); it proves that a
// request comes from whoever created the session. It is not encryption: on
// a shared network anyone who sees a request sees its token (docs/protocol.md).
#pragma once

#include <string>

namespace groundsim::session {

std::string randomHex(int bytes);
inline std::string newToken() { return randomHex(16); }
// 8 upper-case hex digits: short enough for channel names (GROUNDSIM_STATE_<id>).
std::string newSessionId();

// Compares in time independent of where the strings differ.
bool tokensEqual(const std::string& a, const std::string& b);

}  // namespace groundsim::session
