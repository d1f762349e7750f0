// One answer of the service's small HTTP servers: the LCM server's
// /metrics and /health (lcm/metrics.hpp) and the bridge's recordings
// (web/bridge/recordings.hpp), each computed away from its I/O.
#pragma once

#include <string>

namespace groundsim {

struct HttpAnswer {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
};

}  // namespace groundsim
