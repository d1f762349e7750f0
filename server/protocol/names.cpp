#include "names.hpp"

#include <groundsim/request_t.hpp>
#include <groundsim/session_info_t.hpp>
#include <groundsim/state_t.hpp>

namespace groundsim::net {

const char* modeName(int mode) {
  switch (mode) {
    case groundsim::request_t::MODE_REALTIME: return "realtime";
    case groundsim::request_t::MODE_FAST: return "fast";
    case groundsim::request_t::MODE_LOCKSTEP: return "lockstep";
    case groundsim::session_info_t::MODE_VECTORISED: return "vectorised";
  }
  return "?";
}

int modeFromName(const std::string& name) {
  if (name == "realtime") return groundsim::request_t::MODE_REALTIME;
  if (name == "fast") return groundsim::request_t::MODE_FAST;
  if (name == "lockstep") return groundsim::request_t::MODE_LOCKSTEP;
  return 0;
}

const char* statusName(int status) {
  switch (status) {
    case groundsim::state_t::STATUS_RUNNING: return "running";
    case groundsim::state_t::STATUS_PAUSED: return "paused";
    case groundsim::state_t::STATUS_FINISHED: return "finished";
    case groundsim::state_t::STATUS_DIVERGED: return "diverged";
    case groundsim::state_t::STATUS_STOPPED: return "stopped";
  }
  return "?";
}

bool isFinal(int status) {
  return status == groundsim::state_t::STATUS_FINISHED || status == groundsim::state_t::STATUS_DIVERGED ||
         status == groundsim::state_t::STATUS_STOPPED;
}

}  // namespace groundsim::net
