// `groundsim log SESSION... --csv FILE` or `groundsim log --create SCENARIO
// --csv FILE`: records published states with the columns of `groundsim
// run`'s CSV and accounts for every message. LCM drops silently when a
// subscription's queue (30 by default) or the socket buffer overflows, so
// this logger asks for an 8 MiB socket buffer and a deep queue and counts
// every seq that did not arrive:
// - with --create it subscribes before creating, so every seq from 0 counts
//   (a lost seq 0 is a loss); for a session created before, the states
//   before the first one heard are reported, not counted;
// - the end of a session is its final state, or, when that is lost, the
//   server's heartbeat, which lists an ended session with its last seq
//   (the seqs up to it count as lost);
// - no heartbeat for net::kHeartbeatTimeout ends the log with kExitNoServer.
#include <chrono>
#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "common.hpp"
#include "create.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/names.hpp"
#include "protocol/sample.hpp"
#include "protocol/text.hpp"
#include "run/telemetry_csv.hpp"
#include "tokens.hpp"

namespace groundsim::cli {
namespace {

using SteadyClock = std::chrono::steady_clock;

struct Stream {
  long long expect_from = -1;   // first seq that must arrive (0 when this log created the session)
  long long received = 0;
  long long first_seq = -1, last_seq = -1;
  long long gaps = 0, lost = 0, duplicates = 0;
  bool ended = false;
  std::string end_note;         // how the end was learnt, when not from the final state
  std::optional<SteadyClock::time_point> final_listed;  // heartbeat said final before the final state came
  std::optional<long long> missing_since;  // heartbeat rounds when no server listed it (a fleet's handover: for a while)
  // A fleet's failover (docs/fleet.md): the new owner, at a higher epoch,
  // publishes again the seqs from its snapshot on; those are re-simulated,
  // not repeats, and are compared with their first publication. Messages of
  // a lower epoch than one heard come from a fenced old owner: dropped.
  long long epoch = 0;
  long long resimulated = 0, resimulated_same = 0, fenced = 0;
  struct Seen { long long epoch; std::string rows; };
  std::map<long long, Seen> recent;  // the last kRecent seqs' epochs and CSV rows (a snapshot interval's worth)
  static constexpr std::size_t kRecent = 4096;
};

// A seq range that did not arrive.
void countGap(const std::string& id, Stream& st, long long from, long long to) {
  if (to < from) return;
  ++st.gaps;
  st.lost += to - from + 1;
  std::fprintf(stderr, "log: %s: seq %lld..%lld lost (%lld)\n", id.c_str(), from, to, to - from + 1);
}

struct LogOptions {
  NetOptions net;
  CreateOptions create;
  std::vector<std::string> sessions;
  std::string csv;
  double duration = 0.0;
};

// One log, its phases in the order run() takes them. Subscribed handlers
// hold `this`: it is made in place and never moved.
class StateLog {
 public:
  explicit StateLog(const LogOptions& o)
      : o_(o),
        create_(o.create.file.empty() ? std::nullopt : std::optional<CreateRequest>(createRequest(o.create))),
        client_(o.net.url, /*deep_receive=*/true),
        prefix_(o.sessions.size() > 1) {
    for (const auto& s : o_.sessions) streams_[s];
  }
  StateLog(const StateLog&) = delete;
  StateLog& operator=(const StateLog&) = delete;

  // with --create: every state channel, before the create (the id is not known yet)
  void subscribe() {
    std::vector<std::string> channels;
    if (create_) channels.push_back(std::string(net::kStatePrefix) + ".*");
    for (const auto& s : o_.sessions) channels.push_back(net::stateChannel(s));
    for (const auto& ch : channels)
      client_.lcm().subscribe(ch, &StateLog::onMessage, this)->setQueueCapacity(net::kDeepQueue);
  }

  void createIfAsked() {
    if (!create_) return;
    const groundsim::reply_t r = client_.create(create_->req, create_->assets, std::max(o_.net.timeout, 10.0));
    if (!r.ok) fail(kExitRefused, r.error);
    TokenStore(o_.net.token_file).put(r.session_id, r.token, client_.url());
    streams_[r.session_id].expect_from = 0;
    std::fprintf(stderr, "log: created session %s\n", net::printable(r.session_id).c_str());
    std::printf("%s\n", net::printable(r.session_id).c_str());
    std::fflush(stdout);
  }

  // the CSV opened, the states heard before the create's reply written, and
  // the ready line (tests and scripts wait for it instead of sleeping)
  void openOutput() {
    out_ = o_.csv == "-" ? stdout : std::fopen(o_.csv.c_str(), "w");
    if (!out_) fail(kExitRefused, "cannot write " + net::quoted(o_.csv));
    std::setvbuf(out_, nullptr, _IOFBF, 1 << 20);
    std::fprintf(out_, "%s\n", csvHeader().c_str());
    for (const auto& m : early_) record(m);
    early_.clear();
    std::fprintf(stderr, "log: recording %zu session(s) on %s\n", streams_.size(), client_.url().c_str());
  }

  void logUntilEnded() {
    rounds_at_start_ = client_.server().rounds();
    const auto start = SteadyClock::now();
    while (!stopRequested() && !allEnded()) {
      if (o_.duration > 0 && SteadyClock::now() - start > std::chrono::duration<double>(o_.duration)) break;
      try {
        client_.pump(100);
      } catch (const NetError& e) {
        server_lost_ = e.what();
        break;
      }
      checkHeartbeat();
    }
  }

  // what already arrived, then the file closed
  void drainAndClose() {
    while (client_.lcm().handleTimeout(0) > 0) {
    }
    if (out_ != stdout) std::fclose(out_);
    else std::fflush(out_);
  }

  void reportAndExit() const {
    long long lost = 0;
    bool unknown = false;
    for (const auto& [id, st] : streams_) {
      report(id, st);
      lost += st.lost;
      unknown = unknown || (st.received == 0 && st.end_note == "not on the server");
    }
    std::fprintf(stderr, "log: %lld rows written to %s\n", rows_, net::printable(o_.csv).c_str());
    if (server_lost_) fail(kExitNoServer, *server_lost_ + "; " + std::to_string(lost) + " state messages lost before");
    if (unknown) fail(kExitRefused, "a session to log is not on the server");
    if (lost > 0) fail(kExitLoss, std::to_string(lost) + " state messages lost");
  }

 private:
  void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    groundsim::state_t m;
    const auto d = net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.state_t");
    if (!d.ok()) {
      std::fprintf(stderr, "log: %s: %s\n", net::printable(channel).c_str(), d.reason.c_str());
      return;
    }
    if (!out_) {
      if (early_.size() < 1'000'000) early_.push_back(std::move(m));
      return;
    }
    record(m);
  }

  // the rows of a state, "SESSION/vehicle" when mixing sessions
  std::string rowsOf(const groundsim::state_t& m, long long& nrows) const {
    std::string text;
    nrows = 0;
    for (int v = 0; v < m.nvehicles && v < static_cast<int>(m.vehicles.size()); ++v) {
      const std::string name = prefix_ ? m.session_id + "/" + m.vehicles[v].name : m.vehicles[v].name;
      text += csvRow(net::toSample(m, v), name);
      text += '\n';
      ++nrows;
    }
    return text;
  }

  // A seq at or below the newest: published again by a new owner (compared
  // with its first publication), or a repeat. True when it was one of those.
  static bool seenBefore(const std::string& id, Stream& st, const groundsim::state_t& m, const std::string& rows_text) {
    if (st.last_seq < 0 || m.seq > st.last_seq) return false;
    auto seen = st.recent.find(m.seq);
    if (seen != st.recent.end() && seen->second.epoch < m.epoch) {
      ++st.resimulated;  // published again by the session's new owner
      if (seen->second.rows == rows_text) ++st.resimulated_same;
      else if (st.resimulated - st.resimulated_same == 1)  // the first difference, in full
        std::fprintf(stderr, "log: %s: seq %lld re-simulated at epoch %lld differs from its first publication:\n"
                     "  first       %s  re-simulated %s", id.c_str(), static_cast<long long>(m.seq),
                     static_cast<long long>(m.epoch), seen->second.rows.c_str(), rows_text.c_str());
      seen->second.epoch = m.epoch;
      return true;
    }
    ++st.duplicates;  // a reset does not restart seq: this is a repeat
    return true;
  }

  void record(const groundsim::state_t& m) {
    auto it = streams_.find(m.session_id);
    if (it == streams_.end()) return;
    const std::string& id = it->first;
    Stream& st = it->second;
    if (m.epoch < st.epoch) {
      ++st.fenced;  // an old owner's, cut off and not yet silent
      return;
    }
    st.epoch = m.epoch;
    long long nrows = 0;
    const std::string rows_text = rowsOf(m, nrows);
    if (seenBefore(id, st, m, rows_text)) return;
    st.recent[m.seq] = Stream::Seen{m.epoch, rows_text};
    if (st.recent.size() > Stream::kRecent) st.recent.erase(st.recent.begin());
    if (st.last_seq < 0) {
      if (st.expect_from >= 0) countGap(id, st, st.expect_from, m.seq - 1);
      st.first_seq = m.seq;
    } else {
      countGap(id, st, st.last_seq + 1, m.seq - 1);
    }
    st.last_seq = m.seq;
    ++st.received;
    if (net::isFinal(m.status)) st.ended = true;
    std::fputs(rows_text.c_str(), out_);
    rows_ += nrows;
  }

  // the heartbeat tells of ends whose final state was lost
  void checkHeartbeat() {
    const auto now = SteadyClock::now();
    for (auto& [id, st] : streams_) {
      if (st.ended) continue;
      const auto info = client_.server().session(id);
      if (!info) {
        // listed by no server for two rounds of every server's heartbeat: gone (or never there)
        const long long rounds = client_.server().rounds();
        if (!st.missing_since) st.missing_since = rounds;
        if (rounds >= std::max(rounds_at_start_, *st.missing_since) + 2) {
          st.ended = true;
          st.end_note = st.received > 0 ? "no longer on the server; its final state was lost" : "not on the server";
          if (st.received > 0) ++st.lost, ++st.gaps;
        }
        continue;
      }
      st.missing_since.reset();
      if (!net::isFinal(info->status)) continue;
      // final: its state may still be on its way; wait one heartbeat period for it
      if (!st.final_listed) st.final_listed = now;
      if (now - *st.final_listed < std::chrono::duration<double>(net::kHeartbeatPeriod * 1.5)) continue;
      st.ended = true;
      st.end_note = std::string(net::statusName(info->status)) + " (from the server's heartbeat)";
      const long long from = st.last_seq >= 0 ? st.last_seq + 1 : std::max(0LL, st.expect_from);
      if (st.last_seq < 0 && st.expect_from < 0) continue;  // nothing heard, nothing owed
      countGap(id, st, from, info->seq);
    }
  }

  bool allEnded() const {
    for (const auto& [id, st] : streams_)
      if (!st.ended) return false;
    return true;
  }

  static void report(const std::string& id, const Stream& st) {
    std::fprintf(stderr, "log %s: %lld states received (seq %lld..%lld), %lld lost in %lld gaps%s%s\n",
                 net::printable(id).c_str(), st.received, st.first_seq, st.last_seq, st.lost, st.gaps,
                 st.ended ? ", session ended" : "", st.end_note.empty() ? "" : (": " + st.end_note).c_str());
    if (st.resimulated > 0 || st.fenced > 0)
      std::fprintf(stderr,
                   "log %s: %lld states re-simulated after a move (epoch %lld now), %lld identical to their first "
                   "publication, %lld not; %lld from a fenced owner dropped\n",
                   net::printable(id).c_str(), st.resimulated, st.epoch, st.resimulated_same,
                   st.resimulated - st.resimulated_same, st.fenced);
    if (st.expect_from < 0 && st.first_seq > 0)
      std::fprintf(stderr, "log %s: seq 0..%lld were published before this log subscribed (not counted)\n",
                   net::printable(id).c_str(), st.first_seq - 1);
  }

  const LogOptions& o_;
  std::optional<CreateRequest> create_;  // refused before anything is opened
  NetClient client_;
  const bool prefix_;  // vehicle column "SESSION/vehicle" when mixing sessions
  std::map<std::string, Stream> streams_;
  std::vector<groundsim::state_t> early_;  // states heard before the create's reply named the session
  FILE* out_ = nullptr;
  long long rows_ = 0;
  long long rounds_at_start_ = 0;
  std::optional<std::string> server_lost_;
};

void run(const LogOptions& o) {
  installStopSignals();
  StateLog log(o);
  log.subscribe();
  log.createIfAsked();
  log.openOutput();
  log.logUntilEnded();
  log.drainAndClose();
  log.reportAndExit();
}

}  // namespace

void registerLogCommand(CLI::App& app) {
  auto o = std::make_shared<LogOptions>();
  auto* cmd = app.add_subcommand("log", "record sessions' states to CSV (the columns of `groundsim run`)");
  cmd->add_option("SESSION", o->sessions, "session ids (or --create)");
  cmd->add_option("--csv", o->csv, "output file ('-' for stdout)")->required();
  cmd->add_option("--duration", o->duration,
                  "wall seconds to record (0: until every session ends, or SIGINT)")->capture_default_str();
  addCreateOptions(cmd, o->create, /*positional=*/false);
  addNetOptions(cmd, o->net, true);
  cmd->callback([o] {
    if (o->sessions.empty() == o->create.file.empty())
      throw CLI::ValidationError("log", "give SESSION ids or --create SCENARIO (one of the two)");
    guarded([&] { run(*o); });
  });
}

}  // namespace groundsim::cli
