#include "bridge/recordings.hpp"

#include <filesystem>
#include <mutex>
#include <optional>

#include "bridge/recording_files.hpp"
#include "bridge/recording_reads.hpp"
#include "bridge/scene_view.hpp"
#include "bridge/state_json.hpp"

namespace groundsim::web {

HttpAnswer Recordings::answer(const std::string& path, const std::string& query) const {
  if (!enabled()) return errorAnswer(404, "no recordings are served (groundsim-web --recordings DIR)");
  try {
    if (path == "/recordings" || path == "/recordings/") return recordingsListing(dir_);
    std::string rest = path.substr(std::string("/recordings/").size());
    std::string what;
    if (const auto slash = rest.find('/'); slash != std::string::npos) {
      what = rest.substr(slash + 1);
      rest.resize(slash);
    }
    return ofFile(rest, what, query);
  } catch (const std::exception& e) {
    return errorAnswer(500, std::string("cannot read the recording: ") + e.what());
  }
}

HttpAnswer Recordings::ofFile(const std::string& name, const std::string& what, const std::string& query) const {
  if (!plainRecordingName(name))
    return errorAnswer(400, "name: " + web::quoted(name.substr(0, 80)) + " is not a .mcap file name of the folder");
  const std::string file = dir_ + "/" + name;
  if (!std::filesystem::is_regular_file(file)) return errorAnswer(404, "name: no recording " + web::quoted(name));
  if (what.empty()) return {200, "application/json", recordingJson(name, file) + "\n"};
  if (what != "states" && what != "scene" && what != "ground" && what != "events")
    return errorAnswer(404, "no such view: " + web::quoted(what.substr(0, 40)) + " (states, scene, ground, events)");
  const auto q = parseQuery(query);
  auto sit = q.find("session");
  if (sit == q.end() || sit->second.empty() || sit->second.size() > 64)
    return errorAnswer(400, "session: required, the session id (at most 64 characters)");
  const std::string& session = sit->second;
  if (what == "scene" || what == "ground") return sceneOrGround(what, file, name, session, q);
  if (what == "events") return recordedEvents(file, name, session);
  return recordedStates(file, name, session, q);
}

HttpAnswer Recordings::sceneOrGround(const std::string& what, const std::string& file, const std::string& name,
                                     const std::string& session, const Query& q) const {
  std::string why;
  std::optional<double> cx, cy;
  if (what == "ground" && (!(cx = metres(q, "cx", why)) || !(cy = metres(q, "cy", why)))) return errorAnswer(400, why);
  const auto sc = scenes_.get(file, name, session);
  if (!sc->view) return errorAnswer(sc->status, sc->error);
  if (what == "scene")
    return {200, "application/json",
            "{\"session\":" + web::quoted(session) + ",\"layout\":" + sc->view->layout.dump() + "}\n"};
  nlohmann::json grid;
  {
    std::lock_guard<std::mutex> lk(sc->ground_mutex);
    grid = groundGrid(*sc->view->ground, *cx, *cy, grid_n_, grid_step_);
  }
  grid["op"] = "ground";
  grid["session"] = session;
  return {200, "application/json", grid.dump() + "\n"};
}

}  // namespace groundsim::web
