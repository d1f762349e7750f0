// `groundsim inspect FILE.mcap` and `groundsim convert IN OUT`: recordings
// as files (docs/logging.md).
// - inspect: whether the file is complete (a recorder killed mid-way leaves
//   no summary: the reader scans it and says how far it reaches), messages
//   per channel with their time span, the precision of the states' numbers,
//   the ledgers, the attachments.
// - convert: an LCM log (lcm-logger's format) to MCAP, through the same
//   recorder as `record` (JSON messages, ledgers: a seq gap in the log is a
//   loss, named; the raw LCM bytes kept, so it converts back), or an MCAP
//   file with raw LCM bytes (record --raw, or converted) back to an LCM log.
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "net/common.hpp"
#include "protocol/text.hpp"
#include "protocol/message_json.hpp"
#include "record/precision_options.hpp"
#include "record/recorder.hpp"
#include "recording/mcap_reader.hpp"

namespace groundsim::cli {
namespace {

bool endsWith(const std::string& s, const char* suffix) {
  const std::string x(suffix);
  return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

void inspect(const std::string& path) {
  recording::McapReader r(path);
  std::printf("file       %s\n", net::printable(path).c_str());
  std::printf("end        %s\n", r.endNote().c_str());
  std::map<std::uint16_t, std::pair<std::uint64_t, std::uint64_t>> span;
  std::map<std::uint16_t, std::uint64_t> counted;
  r.readMessages([&](const recording::McapMessage& m) {
    auto [it, fresh] = span.try_emplace(m.channel, m.log_time, m.log_time);
    it->second.first = std::min(it->second.first, m.log_time);
    it->second.second = std::max(it->second.second, m.log_time);
    ++counted[m.channel];
  });
  for (const auto& [id, c] : r.channels()) {
    const auto s = span.count(id) ? span[id] : std::pair<std::uint64_t, std::uint64_t>{0, 0};
    std::printf("channel    %-32s %8llu messages, log time %.3f .. %.3f s (%s)\n", net::printable(c.topic).c_str(),
                static_cast<unsigned long long>(counted[id]), 1e-9 * static_cast<double>(s.first),
                1e-9 * static_cast<double>(s.second), c.message_encoding.c_str());
  }
  const auto meta = r.metadata();
  if (auto g = meta.find("groundsim"); g != meta.end()) {
    auto p = g->second.find("json_precision");
    if (p != g->second.end())
      std::printf("precision  %s (the state streams' numbers; docs/logging.md, Size)\n", net::printable(p->second).c_str());
    else if ((p = g->second.find("json_digits")) != g->second.end())
      std::printf("precision  %s significant digits (17: exact)\n", net::printable(p->second).c_str());
  }
  for (const auto& [name, kv] : meta) {
    if (name.rfind("ledger/", 0) != 0) continue;
    std::string line;
    for (const char* k : {"state_received_count", "state_repaired_count", "state_lost_count", "state_lost", "state_resimulated_count",
                          "event_received_count", "event_repaired_count", "event_lost_count", "event_lost"}) {
      auto it = kv.find(k);
      if (it == kv.end()) continue;
      line += std::string(line.empty() ? "" : ", ") + k + " " + (it->second.empty() ? "-" : net::printable(it->second, 200));
    }
    std::printf("%-10s %s\n", name.c_str(), line.c_str());
  }
  for (const auto& [name, data] : r.attachments())
    std::printf("attachment %s (%zu bytes)\n", net::printable(name).c_str(), data.size());
}

// LCM log -> MCAP: every state, car state, contact and event, through the
// recorder (no repair: a gap in the log is a loss).
int lcmToMcap(const std::string& in, const std::string& out, int level, bool raw) {
  lcm::LogFile log(in, "r");
  if (!log.good()) fail(kExitRefused, "cannot read the LCM log " + net::quoted(in));
  recording::WriterOptions wo;
  wo.zstd_level = level;
  wo.profile = "groundsim";
  record::RecorderOptions ro;
  ro.raw = raw;
  record::Recorder rec(std::make_unique<recording::McapWriter>(out, wo), "convert", ro);
  long long events = 0, skipped = 0;
  for (const lcm::LogEvent* ev = log.readNextEvent(); ev; ev = log.readNextEvent()) {
    ++events;
    for (const char* p : {"GROUNDSIM_STATE_", "GROUNDSIM_CAR_STATE_", "GROUNDSIM_CONTACT_", "GROUNDSIM_APPLIED_"})
      if (ev->channel.rfind(p, 0) == 0) rec.add(ev->channel.substr(std::string(p).size()), false);
    if (!rec.onDatagram(ev->channel, static_cast<const std::uint8_t*>(ev->data), ev->datalen)) ++skipped;
  }
  rec.finish();
  for (const auto& line : rec.report()) std::fprintf(stderr, "convert %s\n", net::printable(line, 2000).c_str());
  std::fprintf(stderr, "convert: %lld LCM events read, %lld undecodable skipped, written to %s\n", events, skipped,
               net::printable(out).c_str());
  return rec.totals().lost > 0 ? kExitLoss : 0;
}

// MCAP -> LCM log: the raw LCM bytes (channels "lcm/<channel>") in log time
// order, each event's timestamp the message's log time in microseconds.
int mcapToLcm(const std::string& in, const std::string& out) {
  recording::McapReader r(in);
  std::set<std::uint16_t> raw;
  std::map<std::uint16_t, std::string> channel;
  for (const auto& [id, c] : r.channels())
    if (c.message_encoding == "lcm" && c.topic.rfind("lcm/", 0) == 0) {
      raw.insert(id);
      channel[id] = c.topic.substr(4);
    }
  if (raw.empty())
    fail(kExitRefused, net::quoted(in) + " holds no raw LCM messages (record with --raw, or convert from an LCM log)");
  lcm::LogFile log(out, "w");
  if (!log.good()) fail(kExitRefused, "cannot write " + net::quoted(out));
  long long n = 0;
  r.readMessages(
      [&](const recording::McapMessage& m) {
        lcm::LogEvent ev{};
        ev.eventnum = n++;
        ev.timestamp = static_cast<std::int64_t>(m.log_time / 1000u);
        ev.channel = channel[m.channel];
        ev.datalen = static_cast<std::int32_t>(m.data.size());
        ev.data = const_cast<char*>(m.data.data());
        log.writeEvent(&ev);
      },
      raw);
  std::fprintf(stderr, "convert: %lld LCM events written to %s (%s)\n", n, net::printable(out).c_str(),
               r.endNote().c_str());
  return 0;
}

}  // namespace

void registerRecordingFileCommands(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto* ins = app.add_subcommand("inspect", "what an MCAP recording holds, and whether it is complete");
  ins->add_option("FILE", *path, "an .mcap file")->required();
  ins->callback([path] {
    try {
      inspect(*path);
    } catch (const std::exception& e) {
      fail(kExitRefused, e.what());
    }
  });
  struct ConvertOptions {
    std::string in, out;
    int level = 9;
    record::PrecisionOptions precision;
    bool raw = true;
  };
  auto o = std::make_shared<ConvertOptions>();
  auto* conv = app.add_subcommand("convert", "an LCM log to MCAP (IN.lcm/.log OUT.mcap) or back (IN.mcap OUT)");
  conv->add_option("IN", o->in, "input file")->required();
  conv->add_option("OUT", o->out, "output file")->required();
  conv->add_option("--zstd-level", o->level, "MCAP chunk compression (0: none)")->capture_default_str()
      ->check(CLI::Range(0, 19));
  record::addPrecisionOptions(conv, o->precision);
  conv->add_flag("!--no-raw", o->raw, "LCM to MCAP: leave the raw LCM bytes out (the file cannot convert back)");
  conv->callback([o] {
    record::applyPrecision(o->precision);
    int rc = 0;
    try {
      rc = endsWith(o->in, ".mcap") ? mcapToLcm(o->in, o->out) : lcmToMcap(o->in, o->out, o->level, o->raw);
    } catch (const std::exception& e) {
      fail(kExitRefused, e.what());
    }
    if (rc) fail(rc, "messages were missing from the log (listed above and in the file's ledger)");
  });
}

}  // namespace groundsim::cli
