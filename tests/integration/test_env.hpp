// What both integration test executables share: where the binaries and
// configs are, the loopback-only LCM URL, and small output helpers.
#pragma once

#include <cstdlib>
#include <algorithm>
#include <string>
#include <vector>

#include <unistd.h>

namespace groundsim::itest {

inline const std::string kServer = GROUNDSIM_SERVER_PATH;
inline const std::string kCli = GROUNDSIM_CLI_PATH;
inline const std::string kPlain = std::string(GROUNDSIM_CONFIG_DIR) + "/plain.json";
// ttl=0: packets never leave the host (and each test has its own namespace)
inline const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0";

// A token file of this test process's own, so parallel tests never share one.
inline std::string tokenFile(const std::string& tag) {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/gs-itest-" + tag + "-" + std::to_string(getpid()) + ".json";
}

// --timeout 10 on a client command that does not set its own: the CLI's
// 2 s default for a reply is missed now and then by a server under ASan or
// TSan on a loaded machine, and a test would then fail for the machine.
inline void withReplyTimeout(std::vector<std::string>& args) {
  if (std::find(args.begin(), args.end(), "--timeout") == args.end()) args.insert(args.end(), {"--timeout", "10"});
}

// The last line of a command's output (`create` prints the session id there).
inline std::string lastLine(const std::string& text) {
  std::string s = text;
  while (!s.empty() && s.back() == '\n') s.pop_back();
  const auto nl = s.rfind('\n');
  return nl == std::string::npos ? s : s.substr(nl + 1);
}

}  // namespace groundsim::itest
