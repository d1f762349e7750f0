// mcap_sample: sample MCAP files from McapWriter.
//
//   mcap_sample write FILE [GROUPS [MESSAGES [LEVEL]]]
//       GROUPS sessions (default 100) of MESSAGES smooth ~300-byte JSON
//       states each (default 10000), zstd LEVEL (default 3); prints the raw
//       payload, the file size, the write time and what reading one session
//       back takes.
//   mcap_sample node-check FILE NODE SCRIPT NODE_MODULES...
//       writes a small file (sessions, a channel without messages,
//       attachments, metadata), runs `NODE SCRIPT FILE` (mcap_read.mjs, the
//       npm @mcap/core reader) with the first NODE_MODULES folder holding
//       @mcap/core, and compares its counts with what was written. Exit 77
//       (CTest: skipped) without node or @mcap/core, 1 on a mismatch.
#include <sys/wait.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sample_json.hpp"
#include "recording/mcap_reader.hpp"
#include "recording/mcap_writer.hpp"

namespace fs = std::filesystem;
using namespace groundsim::recording;

namespace {

using groundsim::recording::test::smoothJson;


double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

int writeSample(const std::string& file, int groups, int messages, int level) {
  WriterOptions o;
  o.zstd_level = level;
  std::uint64_t raw = 0;
  std::vector<std::uint16_t> ch;
  double writer_s = 0;  // inside McapWriter's calls
  const auto t_write = std::chrono::steady_clock::now();
  {
    McapWriter w(file, o);
    const std::uint16_t schema = w.addSchema("groundsim.State", "jsonschema", "{}");
    for (int g = 0; g < groups; ++g) ch.push_back(w.addChannel(schema, "/session/" + std::to_string(g) + "/state", "json"));
    for (int i = 0; i < messages; ++i)
      for (int g = 0; g < groups; ++g) {
        const std::string d = smoothJson(g, i);
        const std::uint64_t t = 1'000'000'000ull + i * 10'000'000ull + g;
        const auto t_call = std::chrono::steady_clock::now();
        w.write(ch[g], static_cast<std::uint32_t>(i), t, t, d, g);
        writer_s += since(t_call);
        raw += d.size();
      }
    const auto t_close = std::chrono::steady_clock::now();
    w.close();
    writer_s += since(t_close);
  }
  const double write_s = since(t_write);
  const std::uint64_t size = fs::file_size(file);
  const auto t_read = std::chrono::steady_clock::now();
  McapReader r(file);
  std::uint64_t n = 0;
  r.readMessages([&](const McapMessage&) { ++n; }, {ch[groups / 2]});
  const double read_s = since(t_read);
  std::printf(
      "%d sessions x %d messages, zstd level %d\n"
      "  raw payload   %llu bytes\n"
      "  file          %llu bytes (%.1f %% of raw), %zu chunks\n"
      "  write         %.2f s in all, %.2f s in McapWriter (%.0f MB/s of payload)\n"
      "  one session   %llu messages, %llu bytes read (%.2f %% of the file), %.3f s\n",
      groups, messages, level, static_cast<unsigned long long>(raw), static_cast<unsigned long long>(size),
      100.0 * size / raw, r.chunks().size(), write_s, writer_s, raw / writer_s / 1e6, static_cast<unsigned long long>(n),
      static_cast<unsigned long long>(r.bytesRead()), 100.0 * r.bytesRead() / size, read_s);
  return 0;
}

std::string quote(const std::string& s) {  // for /bin/sh
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

int nodeCheck(const std::string& file, const std::string& node, const std::string& script,
              const std::vector<std::string>& module_dirs) {
  if (node.empty() || node.find("NOTFOUND") != std::string::npos || !fs::exists(node)) {
    std::cout << "SKIP: node not found (apt-get install nodejs)\n";
    return 77;
  }
  std::string modules;
  for (const auto& d : module_dirs)
    if (fs::exists(fs::path(d) / "@mcap" / "core" / "package.json") && fs::exists(fs::path(d) / "fzstd")) {
      modules = d;
      break;
    }
  if (modules.empty()) {
    std::cout << "SKIP: @mcap/core and fzstd not installed (cd web && npm install), looked in:";
    for (const auto& d : module_dirs) std::cout << ' ' << d;
    std::cout << '\n';
    return 77;
  }

  // what we write: 3 sessions x 2 channels, a channel without messages, two
  // schemas, attachments, metadata; small chunks, so there are several
  std::map<std::string, std::uint64_t> topics;
  std::map<std::uint16_t, std::uint64_t> per_channel;
  std::uint64_t messages = 0;
  {
    WriterOptions o;
    o.chunk_bytes = 32 << 10;
    McapWriter w(file, o);
    const std::uint16_t state = w.addSchema("groundsim.State", "jsonschema", R"({"type":"object"})");
    const std::uint16_t drive = w.addSchema("groundsim.Drive", "jsonschema", R"({"type":"object"})");
    std::vector<std::pair<std::uint16_t, std::string>> ch;
    for (int g = 0; g < 3; ++g) {
      const std::string s = "/session/" + std::to_string(g);
      ch.emplace_back(w.addChannel(state, s + "/state", "json", {{"session", std::to_string(g)}}), s + "/state");
      ch.emplace_back(w.addChannel(drive, s + "/drive", "json"), s + "/drive");
    }
    w.addChannel(state, "/never", "json");
    for (int i = 0; i < 700; ++i)
      for (int g = 0; g < 3; ++g) {
        const auto& [id, topic] = ch[2 * g + (i % 5 == 0 ? 1 : 0)];
        const std::uint64_t t = 1'000'000'000ull + i * 20'000'000ull + g * 1000;
        w.write(id, static_cast<std::uint32_t>(i), t, t, smoothJson(g, i), g);
        ++topics[topic];
        ++per_channel[id];
        ++messages;
      }
    w.attach("scenario.json", "application/json", 1'000'000'000ull, R"({"ground":"cosine"})");
    w.attach("track.bin", "application/octet-stream", 2'000'000'000ull, std::string(5000, '\x7f'));
    w.metadata("session", {{"seed", "42"}});
    w.metadata("host", {{"cores", "2"}});
    w.close();
  }
  McapReader ours(file);
  const std::size_t chunks = ours.chunks().size();

  ::setenv("GROUNDSIM_MCAP_NODE_MODULES", modules.c_str(), 1);
  const std::string cmd = quote(node) + " " + quote(script) + " " + quote(file);
  std::FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) {
    std::cerr << "cannot run " << cmd << '\n';
    return 1;
  }
  std::string out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = ::pclose(p);
  if (status != 0) {
    std::cerr << cmd << " failed (status " << status << ")\n" << out << '\n';
    return 1;
  }
  std::cout << "@mcap/core read: " << out;

  nlohmann::json j;
  try {
    j = nlohmann::json::parse(out);
  } catch (const std::exception& e) {
    std::cerr << "not JSON: " << e.what() << '\n';
    return 1;
  }
  int bad = 0;
  auto expect = [&](const char* what, const nlohmann::json& got, const nlohmann::json& want) {
    if (got != want) {
      std::cerr << "MISMATCH " << what << ": @mcap/core says " << got.dump() << ", we wrote " << want.dump() << '\n';
      ++bad;
    }
  };
  nlohmann::json want_topics = nlohmann::json::object();
  for (const auto& [t, n] : topics) want_topics[t] = n;
  nlohmann::json want_counts = nlohmann::json::object();
  for (const auto& [id, n] : per_channel) want_counts[std::to_string(id)] = n;
  expect("library", j["library"], "groundsim");
  expect("messages per topic", j["topics"], want_topics);
  expect("log time order", j["ordered"], true);
  const nlohmann::json& s = j["statistics"];
  expect("statistics.messageCount", s["messageCount"], messages);
  expect("statistics.schemaCount", s["schemaCount"], 2);
  expect("statistics.channelCount", s["channelCount"], 7);
  expect("statistics.attachmentCount", s["attachmentCount"], 2);
  expect("statistics.metadataCount", s["metadataCount"], 2);
  expect("statistics.chunkCount", s["chunkCount"], chunks);
  expect("statistics.channelMessageCounts", s["channelMessageCounts"], want_counts);
  expect("chunk indexes", j["chunkIndexes"], chunks);
  expect("attachments", j["attachments"], nlohmann::json::array({"scenario.json", "track.bin"}));
  expect("metadata", j["metadata"], nlohmann::json::array({"session", "host"}));
  expect("file size", j["fileSize"], fs::file_size(file));
  if (bad == 0) std::cout << "OK: @mcap/core reads what we wrote (" << chunks << " chunks)\n";
  return bad == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> a(argv + 1, argv + argc);
  try {
    if (a.size() >= 2 && a[0] == "write")
      return writeSample(a[1], a.size() > 2 ? std::stoi(a[2]) : 100, a.size() > 3 ? std::stoi(a[3]) : 10000,
                         a.size() > 4 ? std::stoi(a[4]) : 3);
    if (a.size() >= 4 && a[0] == "node-check")
      return nodeCheck(a[1], a[2], a[3], std::vector<std::string>(a.begin() + 4, a.end()));
  } catch (const std::exception& e) {
    std::cerr << "mcap_sample: " << e.what() << '\n';
    return 1;
  }
  std::cerr << "usage: mcap_sample write FILE [GROUPS [MESSAGES [LEVEL]]]\n"
               "       mcap_sample node-check FILE NODE SCRIPT NODE_MODULES...\n";
  return 2;
}
