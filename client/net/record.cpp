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

// One recording, its phases in the order run() takes them. Subscribed
// handlers hold `this`: it is made in place and never moved.
class Recording {
 public:
  explicit Recording(const RecordOptions& o);
  Recording(const Recording&) = delete;
  Recording& operator=(const Recording&) = delete;

  void subscribe();
  void createIfAsked();
  void awaitFirstHeartbeat();
  void recordUntilStopped();
  void drainAndRepairTail();
  void finishAndReport();

 private:
  static std::optional<std::regex> matchOf(const RecordOptions& o);
  static recording::WriterOptions writerOptions(const RecordOptions& o);
  std::unique_ptr<record::Recorder> makeRecorder();
  bool wanted(const std::string& id) const;
  void askScenario(const std::string& id);
  void addNew(const std::string& id);
  void onBus(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onResent(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onBeat(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void sendDue();
  void rotateIfDue();
  void applyBeats(bool add_new);

  const RecordOptions& o_;
  std::optional<CreateRequest> create_;  // refused before anything is opened
  std::optional<std::regex> match_;
  NetClient client_;
  recording::WriterOptions wo_;
  std::unique_ptr<record::Recorder> rec_;
  bool everything_;
  std::set<std::string> asked_scenario_;
  // Sessions that no heartbeat listed since this recorder heard its first
  // one began while it listened: every seq from 0 is owed. Those heard
  // before (or listed by the first heartbeat) began earlier; their seqs
  // before the first one heard are not owed.
  std::set<std::string> listed_first_;
  bool heard_beat_ = false;
  // when a recorded session's message was last handled: the server is
  // alive while they come, even when its heartbeats do not (an overloaded
  // recorder's socket drops heartbeats as it drops states)
  SteadyClock::time_point heard_session_ = SteadyClock::now();
  // when the socket read the newest heartbeat (the recorder's wall clock,
  // set by LCM's receive thread): the stop waits for one read after it
  std::int64_t beat_received_utime_ = 0;
  std::optional<std::string> server_lost_;
  long long beats_seen_ = 0;
  // pump() handles one message: the asks due are looked for every 10 ms,
  // not after each message (requests() walks every session's gaps: at 100
  // sessions that per message cost more than the messages themselves)
  SteadyClock::time_point asked_at_ = SteadyClock::now() - std::chrono::seconds(1);
  // rotation and the disk budget
  std::vector<std::pair<std::string, std::uint64_t>> parts_;  // closed parts, oldest first
  SteadyClock::time_point part_started_ = SteadyClock::now();
};

std::optional<std::regex> Recording::matchOf(const RecordOptions& o) {
  if (o.match.empty()) return std::nullopt;
  try {
    return std::regex(o.match, std::regex::ECMAScript);
  } catch (const std::regex_error& e) {
    fail(kExitUsage, "--match: " + net::quoted(o.match) + " is not a regular expression: " + e.what());
  }
}

recording::WriterOptions Recording::writerOptions(const RecordOptions& o) {
  recording::WriterOptions wo;
  wo.zstd_level = o.zstd_level;
  wo.chunk_seconds = 1.0;
  wo.profile = "groundsim";
  return wo;
}

Recording::Recording(const RecordOptions& o)
    : o_(o),
      create_(o.create.file.empty() ? std::nullopt : std::optional<CreateRequest>(createRequest(o.create))),
      match_(matchOf(o)),
      client_(o.net.url, /*deep_receive=*/true),
      wo_(writerOptions(o)),
      rec_(makeRecorder()),
      everything_(o.all || match_ || create_) {
  for (const auto& s : o_.sessions) rec_->add(s, false);
}

std::unique_ptr<record::Recorder> Recording::makeRecorder() {
  std::unique_ptr<recording::McapWriter> writer;
  try {
    writer = std::make_unique<recording::McapWriter>(partPath(o_, 0), wo_);
  } catch (const std::exception& e) {
    fail(kExitRefused, e.what());
  }
  record::RecorderOptions ro;
  ro.raw = o_.raw;
  return std::make_unique<record::Recorder>(std::move(writer), client_.clientId(), ro);
}

bool Recording::wanted(const std::string& id) const {
  return o_.all || (match_ && std::regex_search(id, *match_));
}

void Recording::askScenario(const std::string& id) {
  if (!asked_scenario_.insert(id).second) return;
  groundsim::request_t r{};
  r.utime = wallMicros();
  r.op = net::kOpScenario;
  r.client_id = client_.clientId();
  r.session_id = id;
  std::vector<std::uint8_t> buf(r.getEncodedSize());
  r.encode(buf.data(), 0, static_cast<int>(buf.size()));
  client_.lcm().publish(net::kRequestChannel, buf.data(), static_cast<unsigned>(buf.size()));
}

void Recording::addNew(const std::string& id) {
  rec_->add(id, heard_beat_ && !listed_first_.count(id));
  askScenario(id);
}

// the session of a state, car state or contact channel ("" for others)
std::string sessionOf(const std::string& ch) {
  for (const char* p : {net::kStatePrefix, net::kCarStatePrefix, net::kContactPrefix, net::kAppliedPrefix})
    if (ch.rfind(p, 0) == 0) return ch.substr(std::string(p).size());
  return "";
}

void Recording::onBus(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  const std::string id = sessionOf(channel);
  if (!id.empty() && rec_->has(id)) heard_session_ = SteadyClock::now();
  if (!id.empty() && !rec_->has(id) && wanted(id)) addNew(id);
  if (!rec_->onDatagram(channel, static_cast<const std::uint8_t*>(rbuf->data), static_cast<int>(rbuf->data_size)))
    std::fprintf(stderr, "record: %s: a message that cannot be decoded, or with a seq out of range (not written)\n",
                 net::printable(channel).c_str());
}

void Recording::onResent(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  groundsim::resent_t m;
  const auto d = net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.resent_t");
  if (!d.ok()) {
    std::fprintf(stderr, "record: %s: %s\n", net::printable(channel).c_str(), d.reason.c_str());
    return;
  }
  rec_->onResent(m, SteadyClock::now());
}

void Recording::onBeat(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  beat_received_utime_ = std::max<std::int64_t>(beat_received_utime_, rbuf->recv_utime);
}

void Recording::subscribe() {
  std::vector<std::string> channels{net::kEventChannel, net::kScenarioChannel, net::kDriveChannel,
                                    net::kControlsChannel};
  if (everything_) {
    for (const char* p : {net::kStatePrefix, net::kCarStatePrefix, net::kContactPrefix, net::kAppliedPrefix})
      channels.push_back(std::string(p) + ".*");
  } else {
    for (const auto& s : o_.sessions)
      for (const std::string& ch :
           {net::stateChannel(s), net::carStateChannel(s), net::contactChannel(s), net::appliedChannel(s)})
        channels.push_back(ch);
  }
  lcm::LCM& lcm = client_.lcm();
  for (const auto& ch : channels) lcm.subscribe(ch, &Recording::onBus, this)->setQueueCapacity(net::kDeepQueue);
  lcm.subscribe(net::kStatusChannel, &Recording::onBeat, this)->setQueueCapacity(net::kDeepQueue);
  lcm.subscribe(net::kResentPrefix + client_.clientId(), &Recording::onResent, this)
      ->setQueueCapacity(net::kDeepQueue);
}

void Recording::createIfAsked() {
  if (create_) {
    const groundsim::reply_t r = client_.create(create_->req, create_->assets, std::max(o_.net.timeout, 10.0));
    if (!r.ok) fail(kExitRefused, r.error);
    TokenStore(o_.net.token_file).put(r.session_id, r.token, client_.url());
    // created here: every seq from 0 is owed (states heard before the
    // reply were added as not created; add() keeps the first)
    rec_->add(r.session_id, true);
    for (const scenario::Asset& a : create_->assets) rec_->addAsset(r.session_id, a.ref.name, a.bytes);
    // the scenario the server published with its reply came before the
    // session was added (and was not kept): ask for it
    askScenario(r.session_id);
    std::printf("%s\n", net::printable(r.session_id).c_str());
    std::fflush(stdout);
  }
  for (const auto& s : o_.sessions) askScenario(s);
}

// the first heartbeat: which sessions were there before (the ready line
// comes after it, so a session created after the line is owed from 0)
void Recording::awaitFirstHeartbeat() {
  try {
    while (client_.server().heartbeats() == 0 && !stopRequested()) client_.pump(20);
  } catch (const NetError& e) {
    server_lost_ = e.what();
  }
  for (const auto& info : client_.server().sessions()) listed_first_.insert(info.session_id);
  heard_beat_ = true;
  std::fprintf(stderr, "record: recording to %s on %s\n", net::printable(o_.out).c_str(), client_.url().c_str());
}

void Recording::sendDue() {
  const auto now = SteadyClock::now();
  if (now - asked_at_ < std::chrono::milliseconds(10)) return;
  asked_at_ = now;
  for (const auto& r : rec_->requests(now)) publish(client_.lcm(), net::kResendChannel, r);
}

void Recording::rotateIfDue() {
  const bool by_size = o_.split_mb > 0 && static_cast<double>(rec_->bytesWritten()) >= o_.split_mb * 1e6;
  const bool by_time = o_.split_s > 0 && SteadyClock::now() - part_started_ > std::chrono::duration<double>(o_.split_s);
  if (!by_size && !by_time) return;
  const std::string done = partPath(o_, rec_->part());
  const std::string next = partPath(o_, rec_->part() + 1);
  std::unique_ptr<recording::McapWriter> w;
  try {
    w = std::make_unique<recording::McapWriter>(next, wo_);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "record: cannot start the next part: %s (going on in %s)\n", e.what(), done.c_str());
    return;
  }
  rec_->rotate(std::move(w));
  std::error_code ec;
  const std::uintmax_t n = std::filesystem::file_size(done, ec);
  parts_.emplace_back(done, ec ? 0 : n);
  part_started_ = SteadyClock::now();
  std::fprintf(stderr, "record: part %s closed, %s started\n", net::printable(done).c_str(), net::printable(next).c_str());
  if (o_.budget_mb <= 0) return;
  std::uint64_t total = rec_->bytesWritten();
  for (const auto& [p, size] : parts_) total += size;
  while (!parts_.empty() && static_cast<double>(total) > o_.budget_mb * 1e6) {
    std::fprintf(stderr, "record: %s deleted: the parts hold %.1f MB, over the %.1f MB budget\n",
                 net::printable(parts_.front().first).c_str(), 1e-6 * static_cast<double>(total), o_.budget_mb);
    std::filesystem::remove(parts_.front().first, ec);
    total -= parts_.front().second;
    parts_.erase(parts_.begin());
  }
}

// what the latest heartbeat says: each session's newest seq is owed
void Recording::applyBeats(bool add_new) {
  if (client_.server().heartbeats() == beats_seen_) return;
  beats_seen_ = client_.server().heartbeats();
  for (const auto& info : client_.server().sessions()) {
    if (!rec_->has(info.session_id)) {
      if (!add_new || !wanted(info.session_id)) continue;
      addNew(info.session_id);
    }
    rec_->onHeartbeat(info.session_id, info.seq, info.status >= groundsim::state_t::STATUS_FINISHED, SteadyClock::now());
  }
}

void Recording::recordUntilStopped() {
  const auto start = SteadyClock::now();
  bool queued = false;  // the last wait handled a message: more may be queued
  while (!stopRequested() && !server_lost_) {
    rotateIfDue();
    if (o_.duration > 0 && SteadyClock::now() - start > std::chrono::duration<double>(o_.duration)) break;
    if (!everything_ && rec_->allEnded() && !rec_->repairing()) break;
    if (create_ && !o_.all && !match_ && rec_->allEnded() && !rec_->repairing()) break;
    // the server is gone when neither its heartbeat nor any recorded
    // session's message came for the heartbeat timeout, judged only with
    // nothing queued (after a long chunk write the queue holds both)
    if (!queued && client_.server().lost() &&
        SteadyClock::now() - heard_session_ > std::chrono::duration<double>(net::kHeartbeatTimeout)) {
      server_lost_ = client_.server().lostMessage(client_.url());
      break;
    }
    queued = client_.lcm().handleTimeout(20) > 0;
    applyBeats(true);
    sendDue();
  }
}

// What was queued when the recording stopped is handled first, up to a
// heartbeat the socket read after the stop: the server's account of every
// seq published before it (an overloaded recorder may be seconds behind the
// bus, and its queue holds the heartbeats too; stopping at the newest seq
// handled left the rest of the queue unaccounted for). Then the tail (what
// was published after the newest heard) and the repairs still outstanding,
// for up to --repair-wait.
void Recording::drainAndRepairTail() {
  if (server_lost_) return;
  const std::int64_t stop_wall = wallMicros();
  const auto drain_cap = SteadyClock::now() + std::chrono::seconds(120);  // the queue is bounded (kDeepQueue)
  auto until = SteadyClock::now() + std::chrono::duration<double>(o_.repair_wait);
  auto quiet_since = SteadyClock::now();
  bool tail_asked = false;
  while (true) {
    const auto now = SteadyClock::now();
    const bool gone =
        client_.server().lost() && now - heard_session_ > std::chrono::duration<double>(net::kHeartbeatTimeout);
    if (!tail_asked && (beat_received_utime_ >= stop_wall || gone)) {
      for (const auto& r : rec_->tailRequests(now)) publish(client_.lcm(), net::kResendChannel, r);
      tail_asked = true;
      until = std::max(until, now + std::chrono::duration<double>(o_.repair_wait));
    }
    if (!tail_asked && now >= drain_cap) {
      std::fprintf(stderr, "record: no heartbeat read after the stop within 120 s: seqs after the newest known "
                           "(listed in the ledger) were not accounted for\n");
      break;
    }
    if (tail_asked && now >= until) break;
    if (client_.lcm().handleTimeout(20) > 0) quiet_since = SteadyClock::now();
    applyBeats(false);
    sendDue();
    if (tail_asked && !rec_->repairing() && SteadyClock::now() - quiet_since > std::chrono::milliseconds(200)) break;
  }
}

void Recording::finishAndReport() {
  rec_->finish();
  for (const auto& line : rec_->report()) std::fprintf(stderr, "record %s\n", net::printable(line, 2000).c_str());
  const auto t = rec_->totals();
  std::fprintf(stderr,
               "record: %lld messages received, %lld repaired, %lld lost, %lld asked for again (%lld bytes resent, "
               "%lld live), %lld undecodable; written to %s\n",
               static_cast<long long>(t.received), static_cast<long long>(t.repaired), static_cast<long long>(t.lost),
               static_cast<long long>(t.asked), static_cast<long long>(t.resent_bytes),
               static_cast<long long>(t.live_bytes), static_cast<long long>(t.undecodable),
               net::printable(partPath(o_, rec_->part())).c_str());
  if (server_lost_) fail(kExitNoServer, *server_lost_);
  if (t.lost > 0) fail(kExitLoss, std::to_string(t.lost) + " messages lost (listed above and in the file's ledger)");
}

void run(const RecordOptions& o) {
  installStopSignals();
  Recording r(o);
  r.subscribe();
  r.createIfAsked();
  r.awaitFirstHeartbeat();
  r.recordUntilStopped();
  r.drainAndRepairTail();
  r.finishAndReport();
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
