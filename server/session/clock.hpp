// Where a session reads the time. Sessions never call Clock::now()
// themselves: the service passes its clock, tests pass a manual one and
// cover pacing, timeouts and overruns without sleeping.
#pragma once

#include "types.hpp"

namespace groundsim::session {

class SessionClock {
 public:
  virtual ~SessionClock() = default;
  virtual TimePoint now() const = 0;
};

// The steady clock; the default of every session and of the service.
const SessionClock& steadyClock();

}  // namespace groundsim::session
