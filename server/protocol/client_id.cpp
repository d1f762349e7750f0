#include "protocol/client_id.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <random>

namespace groundsim::net {

namespace {
std::string clean(std::string s, std::size_t max) {
  if (s.size() > max) s.resize(max);
  for (char& c : s)
    if (c == '/' || static_cast<unsigned char>(c) < 0x21 || static_cast<unsigned char>(c) > 0x7e) c = '_';
  return s;
}

std::string principal() {
  if (const char* named = std::getenv("GROUNDSIM_CLIENT"); named && *named) return clean(named, 48);
  std::string user = "?";
  if (const passwd* pw = ::getpwuid(::getuid()); pw && pw->pw_name) user = pw->pw_name;
  char host[256] = {0};
  if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  return clean(user, 32) + "@" + clean(host[0] ? host : "?", 64);
}
}  // namespace

std::string newClientId(const std::string& kind) {
  std::random_device rd;
  char instance[48];
  std::snprintf(instance, sizeof instance, "/%d-%08x", static_cast<int>(::getpid()), rd());
  return kind + "-" + principal() + instance;
}

}  // namespace groundsim::net
