// Recordings served to browsers (docs/logging.md, "Views"): the MCAP files
// of one folder (groundsim-web --recordings DIR), listed and read with
// server-side seeking, so a replay timeline fetches a window or one instant
// of a session without downloading the file:
//   GET /recordings                     {"recordings":[{name, bytes, complete, end, sessions:[{id, states, t0, t1}]}]}
//   GET /recordings/NAME                one of those
//   GET /recordings/NAME/states?session=ID&from=T0&to=T1[&max=N][&contacts=1]
//                                       {"session","from","to","states":[...],"more":bool}: the states in
//                                       [T0, T1] s of simulation time (at most N, 1000 by default, 5000 at most);
//                                       contacts=1: "contacts":[...] too, the contact states (objects
//                                       with mass, hits) of the same span
//   GET /recordings/NAME/states?session=ID&at=T
//                                       the newest state at or before T (a scrub)
//   GET /recordings/NAME/scene?session=ID
//                                       {"session","layout"}: the scene as a live session's "joined"
//                                       carries it (scene_view.hpp), built from the scenario and the
//                                       assets attached to the file
//   GET /recordings/NAME/ground?session=ID&cx=X&cy=Y
//                                       the ground around (X, Y) as a live "ground" message (groundGrid)
//   GET /recordings/NAME/events?session=ID
//                                       {"session","events":[...],"more":bool}: the session's events
//                                       (laps, gates, hits, warnings), at most 5000
// Only the chunks that hold that session and overlap the window are read
// (the file's chunk indexes). Names are plain file names in the folder;
// anything else is a 400 or 404 naming the parameter and the reason.
//
// Recordings only routes a request to the part that answers it: the
// folder's files (recording_files.hpp), a session's states and events
// (recording_reads.hpp), its scene and ground (recorded_scenes.hpp); the
// query's parameters are read by http_answer.hpp.
#pragma once

#include <string>

#include "bridge/http_answer.hpp"
#include "bridge/recorded_scenes.hpp"

namespace groundsim::web {

class Recordings {
 public:
  // dir "" : no recordings served (every request a 404 saying so).
  // configs_dir: a file the recorded scenario names that the recording does
  // not hold (a session the recorder did not create: its assets are not
  // attached) is looked for there, by its name and the sha256 of the
  // scenario's manifest. A ground grid has grid_n x grid_n nodes grid_step
  // m apart (the live sessions' own).
  explicit Recordings(std::string dir, std::string configs_dir = "", int grid_n = 81, double grid_step = 0.5)
      : dir_(std::move(dir)), grid_n_(grid_n), grid_step_(grid_step), scenes_(std::move(configs_dir)) {}
  bool enabled() const { return !dir_.empty(); }
  // path starts with "/recordings"; query without the '?'. Safe to call
  // from several threads at once.
  HttpAnswer answer(const std::string& path, const std::string& query) const;

 private:
  // GET /recordings/NAME[/VIEW]: name a plain file name of the folder
  HttpAnswer ofFile(const std::string& name, const std::string& what, const std::string& query) const;
  // a session's scene, or its ground around (cx, cy)
  HttpAnswer sceneOrGround(const std::string& what, const std::string& file, const std::string& name,
                           const std::string& session, const Query& q) const;

  std::string dir_;
  int grid_n_;
  double grid_step_;
  RecordedScenes scenes_;
};

}  // namespace groundsim::web
