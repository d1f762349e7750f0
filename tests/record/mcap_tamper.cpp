// For tests of `groundsim replay --resimulate`: copies an MCAP recording
// (schemas, channels, messages, attachments, metadata) with one change.
//   mcap_tamper IN OUT nudge TOPIC SEQ   the message of JSON seq SEQ on TOPIC:
//                                        vehicles[0].position[0] moved to the
//                                        next double up (one unit in the last place)
//   mcap_tamper IN OUT drop TOPIC SEQ    that message left out
//   mcap_tamper IN - find TOPIC TEXT     prints the JSON seq of the first message
//                                        on TOPIC whose text holds TEXT
//   mcap_tamper IN - find-alone TOPIC TEXT
//                                        the same, and exit 3 when the message of
//                                        the next JSON seq on TOPIC has the same
//                                        "tick" (an applied command superseded in
//                                        its tick changes nothing when left out)
// Prints the old and new value (nudge). Exit 1 when the message is not found.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "recording/mcap_reader.hpp"
#include "recording/mcap_writer.hpp"

using namespace groundsim::recording;

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: mcap_tamper IN OUT nudge|drop TOPIC SEQ\n");
    return 2;
  }
  const std::string in = argv[1], out = argv[2], what = argv[3], topic = argv[4];
  McapReader r(in);
  if (what == "find" || what == "find-alone") {
    const std::string text = argv[5];
    long long found = -1;
    std::map<long long, long long> ticks;  // find-alone: every message's seq -> tick on TOPIC
    r.readMessages([&](const McapMessage& m) {
      if (r.channels().at(m.channel).topic != topic) return;
      if (what == "find-alone") {
        const auto j = nlohmann::json::parse(m.data);
        ticks[j.value("seq", -1LL)] = j.value("tick", -1LL);
      }
      if (found < 0 && m.data.find(text) != std::string::npos) found = nlohmann::json::parse(m.data).value("seq", -1LL);
    });
    if (found < 0) return 1;
    std::printf("%lld\n", found);
    // the next command applied in the same tick supersedes this one
    const auto next = ticks.find(found + 1);
    if (what == "find-alone" && next != ticks.end() && next->second == ticks[found]) {
      std::fprintf(stderr, "mcap_tamper: seq %lld is superseded by seq %lld in its tick %lld on %s\n", found,
                   found + 1, next->second, topic.c_str());
      return 3;
    }
    return 0;
  }
  const long long seq = std::stoll(argv[5]);
  McapWriter w(out, WriterOptions{});
  std::map<std::uint16_t, std::uint16_t> schema_ids, channel_ids;
  for (const auto& [id, s] : r.schemas()) schema_ids[id] = w.addSchema(s.name, s.encoding, s.data);
  std::uint16_t target = 0;
  for (const auto& [id, c] : r.channels()) {
    channel_ids[id] = w.addChannel(c.schema_id ? schema_ids.at(c.schema_id) : 0, c.topic, c.message_encoding, c.metadata);
    if (c.topic == topic) target = id;
  }
  for (const auto& [name, data] : r.attachments()) w.attach(name, "application/octet-stream", 0, data);
  for (const auto& [name, kv] : r.metadata()) w.metadata(name, kv);
  bool done = false;
  r.readMessages([&](const McapMessage& m) {
    std::string data = m.data;
    if (m.channel == target && !done) {
      auto j = nlohmann::ordered_json::parse(m.data, nullptr, false);
      if (!j.is_discarded() && j.value("seq", -1LL) == seq) {
        done = true;
        if (what == "drop") return;
        auto& x = j["vehicles"][0]["position"][0];
        const double old = x.get<double>();
        x = std::nextafter(old, INFINITY);
        // as replay prints them: the shortest text that reads back as the same double
        char a[32], b[32];
        *std::to_chars(a, a + 31, old).ptr = 0;
        *std::to_chars(b, b + 31, x.get<double>()).ptr = 0;
        std::printf("%s %s\n", a, b);
        data = j.dump();
      }
    }
    w.write(channel_ids.at(m.channel), m.sequence, m.log_time, m.publish_time, data, m.channel);
  });
  w.close();
  if (!done) {
    std::fprintf(stderr, "mcap_tamper: no message of seq %lld on %s\n", seq, topic.c_str());
    return 1;
  }
  return 0;
}
