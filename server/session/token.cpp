#include "token.hpp"

#include <cctype>
#include <random>

namespace groundsim::session {

std::string randomHex(int bytes) {
  static thread_local std::random_device rd;
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(2 * bytes);
  for (int i = 0; i < bytes; i += 4) {
    unsigned v = rd();
    for (int k = 0; k < 4 && i + k < bytes; ++k, v >>= 8) {
      out.push_back(digits[(v >> 4) & 0xf]);
      out.push_back(digits[v & 0xf]);
    }
  }
  return out;
}

std::string newSessionId() {
  std::string id = randomHex(4);
  for (char& c : id) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return id;
}

bool tokensEqual(const std::string& a, const std::string& b) {
  if (a.size() != b.size() || a.empty()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

}  // namespace groundsim::session
