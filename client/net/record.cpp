// `groundsim record [SESSION...] [--all | --match REGEX | --create SCENARIO]
// --out FILE.mcap [--duration S]`: records sessions into an MCAP file with
// nothing lost silently (docs/logging.md). The bus is read with an 8 MiB
// socket buffer and deep queues; every gap in a session's seqs (and in the
// server's event seqs) is asked for again from the server's resend ring;
// what cannot be had is lost with its range named, in the file's ledger
// and on stderr, and the exit code says so (3). Chunks are closed every
// second, so after a kill -9 all but the last second is readable.
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <regex>
#include <set>

#include <groundsim/request_t.hpp>
#include <groundsim/resend_t.hpp>
#include <groundsim/resent_t.hpp>

#include "common.hpp"
#include "create.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/limits.hpp"
#include "protocol/text.hpp"
#include "protocol/message_json.hpp"
#include "record/precision_options.hpp"
#include "record/recorder.hpp"
#include "tokens.hpp"

namespace groundsim::cli {
namespace {

using SteadyClock = std::chrono::steady_clock;

struct RecordOptions {
  NetOptions net;
  CreateOptions create;
  std::vector<std::string> sessions;
  bool all = false;
  std::string match;
  std::string out;
  double duration = 0.0;
  double repair_wait = 3.0;
  bool raw = false;
  int zstd_level = 9;  // docs/logging.md, Size: 3 is about 4 points of the LCM log bigger
  record::PrecisionOptions precision;
  double split_mb = 0.0;  // a new part once the current one holds this much (0: one file)
  double split_s = 0.0;   // a new part after this many wall seconds (0: never)
  double budget_mb = 0.0; // the parts together at most this much: the oldest are deleted (0: no budget)
};

// The file of part k: --out itself without splitting, else <stem>_<k>.mcap
// (rosbag2's naming).
std::string partPath(const RecordOptions& o, int k) {
  if (o.split_mb <= 0 && o.split_s <= 0) return o.out;
  std::string stem = o.out;
  if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".mcap") == 0) stem.resize(stem.size() - 5);
  return stem + "_" + std::to_string(k) + ".mcap";
}

void publish(lcm::LCM& lcm, const std::string& channel, const groundsim::resend_t& r) {
  std::vector<std::uint8_t> buf(r.getEncodedSize());
  r.encode(buf.data(), 0, static_cast<int>(buf.size()));
  lcm.publish(channel, buf.data(), static_cast<unsigned>(buf.size()));
}

void run(const RecordOptions& o) {
  installStopSignals();
  std::optional<CreateRequest> create;
  if (!o.create.file.empty()) create = createRequest(o.create);  // refused before anything is opened
  std::optional<std::regex> match;
  if (!o.match.empty()) {
    try {
      match.emplace(o.match, std::regex::ECMAScript);
    } catch (const std::regex_error& e) {
      fail(kExitUsage, "--match: " + net::quoted(o.match) + " is not a regular expression: " + e.what());
    }
  }

  NetClient client(o.net.url, /*deep_receive=*/true);
  recording::WriterOptions wo;
  wo.zstd_level = o.zstd_level;
  wo.chunk_seconds = 1.0;
  wo.profile = "groundsim";
  std::unique_ptr<recording::McapWriter> writer;
  try {
    writer = std::make_unique<recording::McapWriter>(partPath(o, 0), wo);
  } catch (const std::exception& e) {
    fail(kExitRefused, e.what());
  }
  record::RecorderOptions ro;
  ro.raw = o.raw;
  record::Recorder rec(std::move(writer), client.clientId(), ro);

  const bool everything = o.all || match || create;
  const auto wanted = [&](const std::string& id) {
    if (o.all) return true;
    if (match && std::regex_search(id, *match)) return true;
    return false;
  };
  std::set<std::string> asked_scenario;
  const auto askScenario = [&](const std::string& id) {
    if (!asked_scenario.insert(id).second) return;
    groundsim::request_t r{};
    r.utime = wallMicros();
    r.op = net::kOpScenario;
    r.client_id = client.clientId();
    r.session_id = id;
    std::vector<std::uint8_t> buf(r.getEncodedSize());
    r.encode(buf.data(), 0, static_cast<int>(buf.size()));
    client.lcm().publish(net::kRequestChannel, buf.data(), static_cast<unsigned>(buf.size()));
  };
  for (const auto& s : o.sessions) rec.add(s, false);

  // the session of a state, car state or contact channel ("" for others)
  const auto sessionOf = [](const std::string& ch) -> std::string {
    for (const char* p : {net::kStatePrefix, net::kCarStatePrefix, net::kContactPrefix, net::kAppliedPrefix})
      if (ch.rfind(p, 0) == 0) return ch.substr(std::string(p).size());
    return "";
  };
  // Sessions that no heartbeat listed since this recorder heard its first
  // one began while it listened: every seq from 0 is owed. Those heard
  // before (or listed by the first heartbeat) began earlier; their seqs
  // before the first one heard are not owed.
  std::set<std::string> listed_first;
  bool heard_beat = false;
  const auto addNew = [&](const std::string& id) {
    rec.add(id, heard_beat && !listed_first.count(id));
    askScenario(id);
  };
  // when a recorded session's message was last handled: the server is
  // alive while they come, even when its heartbeats do not (an overloaded
  // recorder's socket drops heartbeats as it drops states)
  auto heard_session = SteadyClock::now();
  auto onBus = [&](const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const std::string id = sessionOf(channel);
    if (!id.empty() && rec.has(id)) heard_session = SteadyClock::now();
    if (!id.empty() && !rec.has(id) && wanted(id)) addNew(id);
    if (!rec.onDatagram(channel, static_cast<const std::uint8_t*>(rbuf->data), static_cast<int>(rbuf->data_size)))
      std::fprintf(stderr, "record: %s: a message that cannot be decoded, or with a seq out of range (not written)\n",
                   net::printable(channel).c_str());
  };
  auto onResent = [&](const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    groundsim::resent_t m;
    const auto d = net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.resent_t");
    if (!d.ok()) {
      std::fprintf(stderr, "record: %s: %s\n", net::printable(channel).c_str(), d.reason.c_str());
      return;
    }
    rec.onResent(m, SteadyClock::now());
  };
  std::vector<std::string> channels{net::kEventChannel, net::kScenarioChannel, net::kDriveChannel,
                                    net::kControlsChannel};
  if (everything) {
    for (const char* p : {net::kStatePrefix, net::kCarStatePrefix, net::kContactPrefix, net::kAppliedPrefix})
      channels.push_back(std::string(p) + ".*");
  } else {
    for (const auto& s : o.sessions)
      for (const std::string& ch :
           {net::stateChannel(s), net::carStateChannel(s), net::contactChannel(s), net::appliedChannel(s)})
        channels.push_back(ch);
  }
  using Handler = decltype(onBus);
  for (const auto& ch : channels)
    client.lcm()
        .subscribeFunction(ch, +[](const lcm::ReceiveBuffer* b, const std::string& c, Handler* h) { (*h)(b, c); }, &onBus)
        ->setQueueCapacity(net::kDeepQueue);
  // when the socket read the newest heartbeat (the recorder's wall clock,
  // set by LCM's receive thread): the stop waits for one read after it
  std::int64_t beat_received_utime = 0;
  auto onBeat = [&](const lcm::ReceiveBuffer* rbuf, const std::string&) {
    beat_received_utime = std::max<std::int64_t>(beat_received_utime, rbuf->recv_utime);
  };
  using BeatHandler = decltype(onBeat);
  client.lcm()
      .subscribeFunction(net::kStatusChannel, +[](const lcm::ReceiveBuffer* b, const std::string& c, BeatHandler* h) { (*h)(b, c); },
                         &onBeat)
      ->setQueueCapacity(net::kDeepQueue);
  using ResentHandler = decltype(onResent);
  client.lcm()
      .subscribeFunction(net::kResentPrefix + client.clientId(),
                         +[](const lcm::ReceiveBuffer* b, const std::string& c, ResentHandler* h) { (*h)(b, c); },
                         &onResent)
      ->setQueueCapacity(net::kDeepQueue);

  if (create) {
    const groundsim::reply_t r = client.create(create->req, create->assets, std::max(o.net.timeout, 10.0));
    if (!r.ok) fail(kExitRefused, r.error);
    TokenStore(o.net.token_file).put(r.session_id, r.token, client.url());
    // created here: every seq from 0 is owed (states heard before the
    // reply were added as not created; add() keeps the first)
    rec.add(r.session_id, true);
    for (const scenario::Asset& a : create->assets) rec.addAsset(r.session_id, a.ref.name, a.bytes);
    // the scenario the server published with its reply came before the
    // session was added (and was not kept): ask for it
    askScenario(r.session_id);
    std::printf("%s\n", net::printable(r.session_id).c_str());
    std::fflush(stdout);
  }
  for (const auto& s : o.sessions) askScenario(s);
  std::optional<std::string> server_lost;
  // the first heartbeat: which sessions were there before (the ready line
  // comes after it, so a session created after the line is owed from 0)
  try {
    while (client.server().heartbeats() == 0 && !stopRequested()) client.pump(20);
  } catch (const NetError& e) {
    server_lost = e.what();
  }
  for (const auto& info : client.server().sessions()) listed_first.insert(info.session_id);
  heard_beat = true;
  std::fprintf(stderr, "record: recording to %s on %s\n", net::printable(o.out).c_str(), client.url().c_str());

  const auto start = SteadyClock::now();
  long long beats_seen = 0;
  // pump() handles one message: the asks due are looked for every 10 ms,
  // not after each message (requests() walks every session's gaps: at 100
  // sessions that per message cost more than the messages themselves)
  auto asked_at = SteadyClock::now() - std::chrono::seconds(1);
  const auto sendDue = [&] {
    const auto now = SteadyClock::now();
    if (now - asked_at < std::chrono::milliseconds(10)) return;
    asked_at = now;
    for (const auto& r : rec.requests(now)) publish(client.lcm(), net::kResendChannel, r);
  };
  // rotation and the disk budget
  std::vector<std::pair<std::string, std::uint64_t>> parts;  // closed parts, oldest first
  auto part_started = SteadyClock::now();
  const auto rotateIfDue = [&] {
    const bool by_size = o.split_mb > 0 && static_cast<double>(rec.bytesWritten()) >= o.split_mb * 1e6;
    const bool by_time = o.split_s > 0 && SteadyClock::now() - part_started > std::chrono::duration<double>(o.split_s);
    if (!by_size && !by_time) return;
    const std::string done = partPath(o, rec.part());
    const std::string next = partPath(o, rec.part() + 1);
    std::unique_ptr<recording::McapWriter> w;
    try {
      w = std::make_unique<recording::McapWriter>(next, wo);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "record: cannot start the next part: %s (going on in %s)\n", e.what(), done.c_str());
      return;
    }
    rec.rotate(std::move(w));
    std::error_code ec;
    const std::uintmax_t n = std::filesystem::file_size(done, ec);
    parts.emplace_back(done, ec ? 0 : n);
    part_started = SteadyClock::now();
    std::fprintf(stderr, "record: part %s closed, %s started\n", net::printable(done).c_str(), net::printable(next).c_str());
    if (o.budget_mb <= 0) return;
    std::uint64_t total = rec.bytesWritten();
    for (const auto& [p, n] : parts) total += n;
    while (!parts.empty() && static_cast<double>(total) > o.budget_mb * 1e6) {
      std::fprintf(stderr, "record: %s deleted: the parts hold %.1f MB, over the %.1f MB budget\n",
                   net::printable(parts.front().first).c_str(), 1e-6 * static_cast<double>(total), o.budget_mb);
      std::filesystem::remove(parts.front().first, ec);
      total -= parts.front().second;
      parts.erase(parts.begin());
    }
  };
  // what the latest heartbeat says: each session's newest seq is owed
  const auto applyBeats = [&](bool add_new) {
    if (client.server().heartbeats() == beats_seen) return;
    beats_seen = client.server().heartbeats();
    for (const auto& info : client.server().sessions()) {
      if (!rec.has(info.session_id)) {
        if (!add_new || !wanted(info.session_id)) continue;
        addNew(info.session_id);
      }
      rec.onHeartbeat(info.session_id, info.seq, info.status >= groundsim::state_t::STATUS_FINISHED,
                      SteadyClock::now());
    }
  };
  bool queued = false;  // the last wait handled a message: more may be queued
  while (!stopRequested() && !server_lost) {
    rotateIfDue();
    if (o.duration > 0 && SteadyClock::now() - start > std::chrono::duration<double>(o.duration)) break;
    if (!everything && rec.allEnded() && !rec.repairing()) break;
    if (create && !o.all && !match && rec.allEnded() && !rec.repairing()) break;
    // the server is gone when neither its heartbeat nor any recorded
    // session's message came for the heartbeat timeout, judged only with
    // nothing queued (after a long chunk write the queue holds both)
    if (!queued && client.server().lost() &&
        SteadyClock::now() - heard_session > std::chrono::duration<double>(net::kHeartbeatTimeout)) {
      server_lost = client.server().lostMessage(client.url());
      break;
    }
    queued = client.lcm().handleTimeout(20) > 0;
    applyBeats(true);
    sendDue();
  }
  // What was queued when the recording stopped is handled first, up to a
  // heartbeat the socket read after the stop: the server's account of
  // every seq published before it (an overloaded recorder may be seconds
  // behind the bus, and its queue holds the heartbeats too; stopping at
  // the newest seq handled left the rest of the queue unaccounted for).
  // Then the tail (what was published after the newest heard) and the
  // repairs still outstanding, for up to --repair-wait.
  if (!server_lost) {
    const std::int64_t stop_wall = wallMicros();
    const auto drain_cap = SteadyClock::now() + std::chrono::seconds(120);  // the queue is bounded (kDeepQueue)
    auto until = SteadyClock::now() + std::chrono::duration<double>(o.repair_wait);
    auto quiet_since = SteadyClock::now();
    bool tail_asked = false;
    while (true) {
      const auto now = SteadyClock::now();
      const bool gone = client.server().lost() &&
                        now - heard_session > std::chrono::duration<double>(net::kHeartbeatTimeout);
      if (!tail_asked && (beat_received_utime >= stop_wall || gone)) {
        for (const auto& r : rec.tailRequests(now)) publish(client.lcm(), net::kResendChannel, r);
        tail_asked = true;
        until = std::max(until, now + std::chrono::duration<double>(o.repair_wait));
      }
      if (!tail_asked && now >= drain_cap) {
        std::fprintf(stderr, "record: no heartbeat read after the stop within 120 s: seqs after the newest known "
                             "(listed in the ledger) were not accounted for\n");
        break;
      }
      if (tail_asked && now >= until) break;
      if (client.lcm().handleTimeout(20) > 0) quiet_since = SteadyClock::now();
      applyBeats(false);
      sendDue();
      if (tail_asked && !rec.repairing() && SteadyClock::now() - quiet_since > std::chrono::milliseconds(200)) break;
    }
  }
  rec.finish();
  for (const auto& line : rec.report()) std::fprintf(stderr, "record %s\n", net::printable(line, 2000).c_str());
  const auto t = rec.totals();
  std::fprintf(stderr,
               "record: %lld messages received, %lld repaired, %lld lost, %lld asked for again (%lld bytes resent, "
               "%lld live), %lld undecodable; written to %s\n",
               static_cast<long long>(t.received), static_cast<long long>(t.repaired), static_cast<long long>(t.lost),
               static_cast<long long>(t.asked), static_cast<long long>(t.resent_bytes),
               static_cast<long long>(t.live_bytes), static_cast<long long>(t.undecodable),
               net::printable(partPath(o, rec.part())).c_str());
  if (server_lost) fail(kExitNoServer, *server_lost);
  if (t.lost > 0) fail(kExitLoss, std::to_string(t.lost) + " messages lost (listed above and in the file's ledger)");
}

}  // namespace

void registerRecordCommand(CLI::App& app) {
  auto o = std::make_shared<RecordOptions>();
  auto* cmd = app.add_subcommand("record", "record sessions into an MCAP file, repairing gaps (docs/logging.md)");
  cmd->add_option("SESSION", o->sessions, "session ids");
  cmd->add_flag("--all", o->all, "every session, also those created while recording");
  cmd->add_option("--match", o->match, "sessions whose id matches this regular expression");
  cmd->add_option("--out", o->out, "the MCAP file to write")->required();
  cmd->add_option("--duration", o->duration, "wall seconds to record (0: until the sessions end, or SIGINT)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--repair-wait", o->repair_wait, "s to wait at the end for repairs still outstanding")
      ->capture_default_str()->check(CLI::Range(0.0, 600.0));
  cmd->add_flag("--raw", o->raw, "also keep every message's LCM bytes (channels lcm/<channel>)");
  cmd->add_option("--zstd-level", o->zstd_level, "chunk compression (0: none)")->capture_default_str()
      ->check(CLI::Range(0, 19));
  cmd->add_option("--split-mb", o->split_mb, "start a new part (<out>_<k>.mcap) once a part holds this many MB")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--split-s", o->split_s, "start a new part after this many wall seconds")->check(CLI::NonNegativeNumber);
  cmd->add_option("--budget-mb", o->budget_mb, "delete the oldest parts while all of them hold more than this")
      ->check(CLI::NonNegativeNumber);
  record::addPrecisionOptions(cmd, o->precision);
  addCreateOptions(cmd, o->create, /*positional=*/false);
  addNetOptions(cmd, o->net, true);
  cmd->callback([o] {
    const int ways = !o->sessions.empty() + o->all + !o->match.empty() + !o->create.file.empty();
    if (ways != 1) throw CLI::ValidationError("record", "give SESSION ids, --all, --match REGEX or --create SCENARIO (one of them)");
    record::applyPrecision(o->precision);
    guarded([&] { run(*o); });
  });
}

}  // namespace groundsim::cli
