// Names of the wire enums (request_t.MODE_*, state_t.STATUS_*), for every
// client: the same words the server uses in its messages.
#pragma once

#include <string>

namespace groundsim::net {

const char* modeName(int mode);      // "realtime", "fast", "lockstep", "?"
int modeFromName(const std::string& name);  // 0 if unknown
const char* statusName(int status);  // "running", "paused", "finished", "diverged", "stopped", "?"
bool isFinal(int status);            // finished, diverged or stopped: no state follows

}  // namespace groundsim::net
