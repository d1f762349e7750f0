#include "bridge/recorded_scenes.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "bridge/scene_view.hpp"
#include "bridge/state_json.hpp"
#include "recording/mcap_reader.hpp"
#include "scenario/assets.hpp"
#include "scenario/file_access.hpp"

namespace groundsim::web {
namespace {

// The file named `ref` in configs_dir or below whose bytes have its sha256
// (at most 2000 entries looked at, files up to 64 MiB read); null if none.
std::shared_ptr<const std::string> findByHash(const std::string& configs_dir, const scenario::AssetRef& ref) {
  namespace fs = std::filesystem;
  if (configs_dir.empty() || ref.size > (64u << 20)) return nullptr;
  const std::string base = fs::path(ref.name).filename().string();
  std::error_code ec;
  int seen = 0;
  for (fs::recursive_directory_iterator it(configs_dir, ec), end; !ec && it != end && seen < 2000; it.increment(ec), ++seen) {
    if (it->path().filename() != base || !it->is_regular_file(ec) || it->file_size(ec) != ref.size) continue;
    std::ifstream in(it->path(), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (scenario::sha256Hex(bytes) == ref.sha256) return std::make_shared<const std::string>(std::move(bytes));
  }
  return nullptr;
}

}  // namespace

std::shared_ptr<RecordedScenes::Scene> RecordedScenes::get(const std::string& file, const std::string& name,
                                                           const std::string& session) const {
  const std::string key = name + "\n" + session;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    for (auto it = scenes_.begin(); it != scenes_.end(); ++it)
      if ((*it)->key == key) {
        scenes_.splice(scenes_.end(), scenes_, it);
        return scenes_.back();
      }
  }
  // built outside the lock: a large ground takes a while, other replays go on
  auto sc = std::make_shared<Scene>();
  sc->key = key;
  build(*sc, file, name, session);
  std::lock_guard<std::mutex> lk(mutex_);
  scenes_.push_back(sc);
  while (scenes_.size() > kScenes) scenes_.pop_front();
  return sc;
}

void RecordedScenes::build(Scene& sc, const std::string& file, const std::string& name,
                           const std::string& session) const {
  try {
    recording::McapReader r(file);
    std::string scenario;
    auto assets = std::make_shared<scenario::AssetBytes>();
    const std::string prefix = "assets/" + session + "/";
    for (auto& [n, data] : r.attachments()) {
      if (n == "scenario/" + session + ".json") scenario = std::move(data);
      else if (n.rfind(prefix, 0) == 0)
        (*assets)[n.substr(prefix.size())] = std::make_shared<const std::string>(std::move(data));
    }
    if (scenario.empty()) {
      sc.status = 404;
      sc.error = "session: " + web::quoted(session) + " has no scenario in " + web::quoted(name) +
                 " (scenario/" + session + ".json is not attached): its scene cannot be drawn";
    } else {
      // files the recording does not hold: the shipped ones, by name and hash
      for (const scenario::AssetRef& ref : scenario::assetManifest(nlohmann::json::parse(scenario)))
        if (!assets->count(ref.name))
          if (auto bytes = findByHash(configs_dir_, ref)) (*assets)[ref.name] = std::move(bytes);
      sc.view = makeSceneView(scenario, scenario::FileAccess::fromAssets(assets));
    }
  } catch (const std::exception& e) {
    sc.status = 422;
    sc.error = "the recorded scenario of session " + session + " cannot be built: " + e.what();
  }
}

}  // namespace groundsim::web
