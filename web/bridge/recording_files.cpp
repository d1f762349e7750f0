#include "bridge/recording_files.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <vector>

#include "bridge/state_json.hpp"
#include "recording/mcap_reader.hpp"

namespace groundsim::web {
namespace {

constexpr int kMaxListed = 200;  // files in a listing

}  // namespace

bool plainRecordingName(const std::string& n) {
  if (n.size() < 6 || n.size() > 200 || n.compare(n.size() - 5, 5, ".mcap") != 0 || n[0] == '.') return false;
  for (unsigned char c : n)
    if (!(std::isalnum(c) || c == '.' || c == '_' || c == '-')) return false;
  return true;
}

// The file's sessions: state channels "/<id>/state" with their counts and
// time spans (from the statistics and chunk indexes when complete).
std::string recordingJson(const std::string& name, const std::string& path) {
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

HttpAnswer recordingsListing(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (e.is_regular_file() && plainRecordingName(n)) names.push_back(n);
  }
  std::sort(names.begin(), names.end());
  std::string out = "{\"recordings\":[";
  int k = 0;
  for (const auto& n : names) {
    if (k == kMaxListed) break;
    std::string one;
    try {
      one = recordingJson(n, dir + "/" + n);
    } catch (const std::exception& e) {
      one = "{\"name\":" + web::quoted(n) + ",\"error\":" + web::quoted(e.what()) + "}";
    }
    out += (k++ ? "," : "") + one;
  }
  return {200, "application/json", out + "],\"more\":" + (static_cast<int>(names.size()) > kMaxListed ? "true" : "false") + "}\n"};
}

}  // namespace groundsim::web
