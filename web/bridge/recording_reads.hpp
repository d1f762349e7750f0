// What a recorded session's messages answer over HTTP (recordings.hpp): a
// window or one instant of its states (with seeking: only the chunks that
// hold the session and overlap the window are read), and its events.
#pragma once

#include <string>

#include "bridge/http_answer.hpp"

namespace groundsim::web {

// GET .../states?session=ID&from=T0&to=T1[&max=N][&contacts=1] or ...&at=T
// of the file at `file` (called `name` in errors). Throws what the MCAP reader throws.
HttpAnswer recordedStates(const std::string& file, const std::string& name, const std::string& session,
                          const Query& q);

// GET .../events?session=ID: at most 5000 of the session's events.
HttpAnswer recordedEvents(const std::string& file, const std::string& name, const std::string& session);

}  // namespace groundsim::web
