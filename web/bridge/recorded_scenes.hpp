// Recorded sessions' scenes (recordings.hpp): a session's scene view built
// from the scenario and the assets attached to its recording, and files the
// recording does not hold looked for among the configs by name and sha256.
// Built once and kept: a replay asks for its ground every few metres. Safe
// to use from several threads at once.
#pragma once

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>

namespace groundsim::web {

struct SceneView;

class RecordedScenes {
 public:
  // A recorded session's scene, or why there is none.
  struct Scene {
    std::string key;          // file name, its size and time, session
    std::shared_ptr<SceneView> view;
    std::string error;        // why it cannot be built
    int status = 0;           // and the answer that says so: 404 (no scenario), 422 (it does not build)
    std::mutex ground_mutex;  // a view's ground is used by one thread at a time
  };

  // configs_dir: where a file the recorded scenario names and the recording
  // does not hold is looked for ("": nowhere).
  explicit RecordedScenes(std::string configs_dir) : configs_dir_(std::move(configs_dir)) {}

  // The scene of `session` in the file at `file` (called `name`): kept, or
  // built now (outside the lock). At most kScenes kept, the newest used last.
  std::shared_ptr<Scene> get(const std::string& file, const std::string& name, const std::string& session) const;

 private:
  static constexpr std::size_t kScenes = 4;
  void build(Scene& sc, const std::string& file, const std::string& name, const std::string& session) const;

  std::string configs_dir_;
  mutable std::mutex mutex_;
  mutable std::list<std::shared_ptr<Scene>> scenes_;
};

}  // namespace groundsim::web
