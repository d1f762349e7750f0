// Recordings served to browsers (docs/logging.md, "Views"): the MCAP files
// of one folder (groundsim-web --recordings DIR), listed and read with
// server-side seeking, so a replay timeline fetches a window or one instant
// of a session without downloading the file:
//   GET /recordings                     {"recordings":[{name, bytes, complete, end, sessions:[{id, states, t0, t1}]}]}
//   GET /recordings/NAME                one of those
//   GET /recordings/NAME/states?session=ID&from=T0&to=T1[&max=N]
//                                       {"session","from","to","states":[...],"more":bool}: the states in
//                                       [T0, T1] s of simulation time (at most N, 1000 by default, 5000 at most)
//   GET /recordings/NAME/states?session=ID&at=T
//                                       the newest state at or before T (a scrub)
// Only the chunks that hold that session and overlap the window are read
// (the file's chunk indexes). Names are plain file names in the folder;
// anything else is a 400 or 404 naming the parameter and the reason.
#pragma once

#include <string>

namespace groundsim::web {

struct HttpAnswer {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
};

class Recordings {
 public:
  // dir "" : no recordings served (every request a 404 saying so)
  explicit Recordings(std::string dir) : dir_(std::move(dir)) {}
  bool enabled() const { return !dir_.empty(); }
  // path starts with "/recordings"; query without the '?'
  HttpAnswer answer(const std::string& path, const std::string& query) const;

 private:
  std::string dir_;
};

}  // namespace groundsim::web
