#include "bridge/recordings.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "bridge/scene_view.hpp"
#include "bridge/state_json.hpp"
#include "recording/mcap_reader.hpp"
#include "scenario/assets.hpp"
#include "scenario/file_access.hpp"

namespace groundsim::web {
namespace {

constexpr int kMaxListed = 200;         // files in a listing
constexpr int kDefaultStates = 1000;
constexpr int kMaxStates = 5000;
constexpr std::size_t kMaxBody = 16u << 20;
constexpr int kMaxEvents = 5000;

HttpAnswer error(int status, const std::string& why) {
  return {status, "application/json", "{\"error\":" + web::quoted(why) + "}\n"};
}

bool plainName(const std::string& n) {
  if (n.size() < 6 || n.size() > 200 || n.compare(n.size() - 5, 5, ".mcap") != 0 || n[0] == '.') return false;
  for (unsigned char c : n)
    if (!(std::isalnum(c) || c == '.' || c == '_' || c == '-')) return false;
  return true;
}

std::string decode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') out += ' ';
    else if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
             std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out += static_cast<char>(std::strtol(s.substr(i + 1, 2).c_str(), nullptr, 16));
      i += 2;
    } else out += s[i];
  }
  return out;
}

std::map<std::string, std::string> parseQuery(const std::string& q) {
  std::map<std::string, std::string> out;
  std::size_t at = 0;
  while (at <= q.size() && out.size() < 16) {
    const std::size_t amp = q.find('&', at);
    const std::string part = q.substr(at, amp == std::string::npos ? std::string::npos : amp - at);
    const std::size_t eq = part.find('=');
    if (!part.empty()) out[decode(part.substr(0, eq))] = eq == std::string::npos ? "" : decode(part.substr(eq + 1));
    if (amp == std::string::npos) break;
    at = amp + 1;
  }
  return out;
}

// A number of seconds: finite, within a day of simulated time squared away
// from overflow when turned into nanoseconds.
std::optional<double> seconds(const std::map<std::string, std::string>& q, const char* key, std::string& why) {
  auto it = q.find(key);
  if (it == q.end()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end || !std::isfinite(v) || v < 0 || v > 1e9) {
    why = std::string(key) + ": must be a number of seconds in [0, 1e9], got " + web::quoted(it->second.substr(0, 40));
    return std::nullopt;
  }
  return v;
}

// A coordinate in metres: finite and within the scenario layer's world.
std::optional<double> metres(const std::map<std::string, std::string>& q, const char* key, std::string& why) {
  auto it = q.find(key);
  if (it == q.end()) {
    why = std::string(key) + ": required, a coordinate in metres";
    return std::nullopt;
  }
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end || !std::isfinite(v) || std::abs(v) > 1e7) {
    why = std::string(key) + ": must be a number of metres in [-1e7, 1e7], got " + web::quoted(it->second.substr(0, 40));
    return std::nullopt;
  }
  return v;
}

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

std::uint64_t ns(double s) { return static_cast<std::uint64_t>(std::llround(s * 1e9)); }

// The file's sessions: state channels "/<id>/state" with their counts and
// time spans (from the statistics and chunk indexes when complete).
std::string fileJson(const std::string& name, const std::string& path) {
  recording::McapReader r(path);
  std::map<std::uint16_t, std::string> ids;
  for (const auto& [id, c] : r.channels())
    if (c.topic.size() > 7 && c.topic[0] == '/' && c.topic.compare(c.topic.size() - 6, 6, "/state") == 0)
      ids[id] = c.topic.substr(1, c.topic.size() - 7);
  const auto counts = r.messageCounts();
  std::map<std::uint16_t, std::pair<std::uint64_t, std::uint64_t>> span;
  for (const auto& ch : r.chunks())
    for (std::uint16_t id : ch.channels) {
      if (!ids.count(id)) continue;
      auto [it, fresh] = span.try_emplace(id, ch.message_start_time, ch.message_end_time);
      it->second.first = std::min(it->second.first, ch.message_start_time);
      it->second.second = std::max(it->second.second, ch.message_end_time);
    }
  std::string out = "{\"name\":" + web::quoted(name) + ",\"bytes\":" + std::to_string(std::filesystem::file_size(path)) +
                    ",\"complete\":" + (r.complete() ? "true" : "false") + ",\"end\":" + web::quoted(r.endNote()) +
                    ",\"sessions\":[";
  bool first = true;
  for (const auto& [id, sid] : ids) {
    const auto c = counts.count(id) ? counts.at(id) : 0;
    const auto s = span.count(id) ? span.at(id) : std::pair<std::uint64_t, std::uint64_t>{0, 0};
    char b[96];
    std::snprintf(b, sizeof b, ",\"states\":%llu,\"t0\":%.6f,\"t1\":%.6f}", static_cast<unsigned long long>(c),
                  1e-9 * static_cast<double>(s.first), 1e-9 * static_cast<double>(s.second));
    out += std::string(first ? "" : ",") + "{\"id\":" + web::quoted(sid) + b;
    first = false;
  }
  return out + "]}";
}

}  // namespace

HttpAnswer Recordings::answer(const std::string& path, const std::string& query) const {
  if (!enabled()) return error(404, "no recordings are served (groundsim-web --recordings DIR)");
  try {
    if (path == "/recordings" || path == "/recordings/") return listing();
    std::string rest = path.substr(std::string("/recordings/").size());
    std::string what;
    if (const auto slash = rest.find('/'); slash != std::string::npos) {
      what = rest.substr(slash + 1);
      rest.resize(slash);
    }
    if (!plainName(rest)) return error(400, "name: " + web::quoted(rest.substr(0, 80)) + " is not a .mcap file name of the folder");
    const std::string file = dir_ + "/" + rest;
    if (!std::filesystem::is_regular_file(file)) return error(404, "name: no recording " + web::quoted(rest));
    if (what.empty()) return {200, "application/json", fileJson(rest, file) + "\n"};
    if (what != "states" && what != "scene" && what != "ground" && what != "events")
      return error(404, "no such view: " + web::quoted(what.substr(0, 40)) + " (states, scene, ground, events)");
    const auto q = parseQuery(query);
    auto sit = q.find("session");
    if (sit == q.end() || sit->second.empty() || sit->second.size() > 64)
      return error(400, "session: required, the session id (at most 64 characters)");
    const std::string& session = sit->second;
    if (what == "scene" || what == "ground") return sceneOrGround(what, file, rest, session, q);
    if (what == "events") return events(file, rest, session);
    return states(file, rest, session, q);
  } catch (const std::exception& e) {
    return error(500, std::string("cannot read the recording: ") + e.what());
  }
}

HttpAnswer Recordings::listing() const {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir_)) {
    const std::string n = e.path().filename().string();
    if (e.is_regular_file() && plainName(n)) names.push_back(n);
  }
  std::sort(names.begin(), names.end());
  std::string out = "{\"recordings\":[";
  int k = 0;
  for (const auto& n : names) {
    if (k == kMaxListed) break;
    std::string one;
    try {
      one = fileJson(n, dir_ + "/" + n);
    } catch (const std::exception& e) {
      one = "{\"name\":" + web::quoted(n) + ",\"error\":" + web::quoted(e.what()) + "}";
    }
    out += (k++ ? "," : "") + one;
  }
  return {200, "application/json", out + "],\"more\":" + (static_cast<int>(names.size()) > kMaxListed ? "true" : "false") + "}\n"};
}

HttpAnswer Recordings::sceneOrGround(const std::string& what, const std::string& file, const std::string& name,
                                     const std::string& session, const Query& q) const {
  std::string why;
  std::optional<double> cx, cy;
  if (what == "ground" && (!(cx = metres(q, "cx", why)) || !(cy = metres(q, "cy", why)))) return error(400, why);
  const auto sc = scene(file, name, session);
  if (!sc->view) return error(sc->status, sc->error);
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

HttpAnswer Recordings::events(const std::string& file, const std::string& name, const std::string& session) const {
  recording::McapReader r(file);
  std::optional<std::uint16_t> channel;
  for (const auto& [id, c] : r.channels())
    if (c.topic == "/" + session + "/events") channel = id;
  if (!channel) return error(404, "session: " + web::quoted(session) + " has no events in " + web::quoted(name));
  std::string out = "{\"session\":" + web::quoted(session) + ",\"events\":[";
  int n = 0;
  bool more = false;
  r.readMessages(
      [&](const recording::McapMessage& m) {
        if (n >= kMaxEvents || out.size() + m.data.size() > kMaxBody) {
          more = true;
          return;
        }
        out += (n++ ? "," : "") + m.data;
      },
      {*channel});
  return {200, "application/json", out + "],\"more\":" + (more ? "true" : "false") + "}\n"};
}

HttpAnswer Recordings::states(const std::string& file, const std::string& name, const std::string& session,
                              const Query& q) const {
  std::string why;
  const auto at = seconds(q, "at", why);
  const auto from = seconds(q, "from", why);
  const auto to = seconds(q, "to", why);
  if (!why.empty()) return error(400, why);
  if (!at && !(from && to)) return error(400, "give at=T, or from=T0 and to=T1 (s of simulation time)");
  if (from && to && *to < *from) return error(400, "to: must be >= from");
  int max = kDefaultStates;
  if (auto m = q.find("max"); m != q.end()) {
    char* end = nullptr;
    const long v = std::strtol(m->second.c_str(), &end, 10);
    if (m->second.empty() || *end || v < 1 || v > kMaxStates)
      return error(400, "max: must be an integer in [1, " + std::to_string(kMaxStates) + "], got " + web::quoted(m->second.substr(0, 40)));
    max = static_cast<int>(v);
  }
  bool with_contacts = false;
  if (auto c = q.find("contacts"); c != q.end()) {
    if (c->second != "0" && c->second != "1") return error(400, "contacts: must be 0 or 1, got " + web::quoted(c->second.substr(0, 40)));
    with_contacts = c->second == "1";
  }
  recording::McapReader r(file);
  std::optional<std::uint16_t> channel, contact_channel;
  for (const auto& [id, c] : r.channels()) {
    if (c.topic == "/" + session + "/state") channel = id;
    if (c.topic == "/" + session + "/contact") contact_channel = id;
  }
  if (!channel) return error(404, "session: " + web::quoted(session) + " is not in " + web::quoted(name));
  std::vector<std::string> states, contacts;
  std::size_t bytes = 0;
  bool more = false;
  if (at) {
    // the newest at or before T: the second before it holds one at any
    // publish rate above 1 Hz; else the whole span before T
    std::string last;
    const std::uint64_t t = ns(*at);
    for (std::uint64_t back : {std::uint64_t{1'000'000'000}, t}) {
      r.readMessages([&](const recording::McapMessage& m) { last = m.data; }, {*channel}, t > back ? t - back : 0, t);
      if (!last.empty()) break;
    }
    if (!last.empty()) states.push_back(std::move(last));
  } else {
    // states and (contacts=1) the contact states beside them (objects
    // with mass, hits), in one pass; a window cut at `max` states is cut
    // for both at the last state's time
    std::set<std::uint16_t> wanted{*channel};
    if (with_contacts && contact_channel) wanted.insert(*contact_channel);
    std::uint64_t cut_at = 0;
    r.readMessages(
        [&](const recording::McapMessage& m) {
          if (more && m.log_time > cut_at) return;
          const bool state = m.channel == *channel;
          if (bytes + m.data.size() > kMaxBody || (state && static_cast<int>(states.size()) >= max)) {
            if (!more) cut_at = m.log_time > 0 ? m.log_time - 1 : 0;
            more = true;
            return;
          }
          bytes += m.data.size();
          (state ? states : contacts).push_back(m.data);
        },
        wanted, ns(*from), ns(*to));
  }
  std::string out = "{\"session\":" + web::quoted(session) + ",\"states\":[";
  for (std::size_t i = 0; i < states.size(); ++i) out += (i ? "," : "") + states[i];
  if (with_contacts) {
    out += "],\"contacts\":[";
    for (std::size_t i = 0; i < contacts.size(); ++i) out += (i ? "," : "") + contacts[i];
  }
  return {200, "application/json", out + "],\"more\":" + (more ? "true" : "false") + "}\n"};
}

std::shared_ptr<Recordings::Scene> Recordings::scene(const std::string& file, const std::string& name,
                                                    const std::string& session) const {
  const std::string key = name + "\n" + session;
  {
    std::lock_guard<std::mutex> lk(scenes_mutex_);
    for (auto it = scenes_.begin(); it != scenes_.end(); ++it)
      if ((*it)->key == key) {
        scenes_.splice(scenes_.end(), scenes_, it);
        return scenes_.back();
      }
  }
  // built outside the lock: a large ground takes a while, other replays go on
  auto sc = std::make_shared<Scene>();
  sc->key = key;
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
      sc->status = 404;
      sc->error = "session: " + web::quoted(session) + " has no scenario in " + web::quoted(name) +
                  " (scenario/" + session + ".json is not attached): its scene cannot be drawn";
    } else {
      // files the recording does not hold: the shipped ones, by name and hash
      for (const scenario::AssetRef& ref : scenario::assetManifest(nlohmann::json::parse(scenario)))
        if (!assets->count(ref.name))
          if (auto bytes = findByHash(configs_dir_, ref)) (*assets)[ref.name] = std::move(bytes);
      sc->view = makeSceneView(scenario, scenario::FileAccess::fromAssets(assets));
    }
  } catch (const std::exception& e) {
    sc->status = 422;
    sc->error = "the recorded scenario of session " + session + " cannot be built: " + e.what();
  }
  std::lock_guard<std::mutex> lk(scenes_mutex_);
  scenes_.push_back(sc);
  while (scenes_.size() > kScenes) scenes_.pop_front();
  return sc;
}

}  // namespace groundsim::web
