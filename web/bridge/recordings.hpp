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
#pragma once

#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace groundsim::web {

struct SceneView;

struct HttpAnswer {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
};

class Recordings {
 public:
  // dir "" : no recordings served (every request a 404 saying so).
  // configs_dir: a file the recorded scenario names that the recording does
  // not hold (a session the recorder did not create: its assets are not
  // attached) is looked for there, by its name and the sha256 of the
  // scenario's manifest. A ground grid has grid_n x grid_n nodes grid_step
  // m apart (the live sessions' own).
  explicit Recordings(std::string dir, std::string configs_dir = "", int grid_n = 81, double grid_step = 0.5)
      : dir_(std::move(dir)), configs_dir_(std::move(configs_dir)), grid_n_(grid_n), grid_step_(grid_step) {}
  bool enabled() const { return !dir_.empty(); }
  // path starts with "/recordings"; query without the '?'. Safe to call
  // from several threads at once.
  HttpAnswer answer(const std::string& path, const std::string& query) const;

 private:
  // A recorded session's scene, built once: a replay asks for its ground
  // every few metres. At most kScenes kept (the newest used last).
  struct Scene {
    std::string key;          // file name, its size and time, session
    std::shared_ptr<SceneView> view;
    std::string error;        // why it cannot be built
    int status = 0;           // and the answer that says so: 404 (no scenario), 422 (it does not build)
    std::mutex ground_mutex;  // a view's ground is used by one thread at a time
  };
  static constexpr std::size_t kScenes = 4;
  std::shared_ptr<Scene> scene(const std::string& file, const std::string& name, const std::string& session) const;

  // the views answer() routes to: GET /recordings, and of one file (name,
  // its path) a session's scene or ground, events, or states
  using Query = std::map<std::string, std::string>;
  HttpAnswer listing() const;
  HttpAnswer sceneOrGround(const std::string& what, const std::string& file, const std::string& name,
                           const std::string& session, const Query& q) const;
  HttpAnswer events(const std::string& file, const std::string& name, const std::string& session) const;
  HttpAnswer states(const std::string& file, const std::string& name, const std::string& session,
                    const Query& q) const;

  std::string dir_, configs_dir_;
  int grid_n_;
  double grid_step_;
  mutable std::mutex scenes_mutex_;
  mutable std::list<std::shared_ptr<Scene>> scenes_;
};

}  // namespace groundsim::web
