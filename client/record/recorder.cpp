#include "record/recorder.hpp"

#include <algorithm>
#include <cstdio>

#include <groundsim/applied_t.hpp>
#include <groundsim/car_state_t.hpp>
#include <groundsim/contact_state_t.hpp>
#include <groundsim/controls_t.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/scenario_t.hpp>
#include <groundsim/state_t.hpp>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/message_json.hpp"

namespace groundsim::record {
namespace {

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

std::uint64_t ns(std::int64_t utime) { return utime > 0 ? static_cast<std::uint64_t>(utime) * 1000u : 0u; }

// Seqs count messages from 0; a datagram claiming one outside [0, 2^53)
// (a foreign or forged publisher) is not written, so ledger arithmetic
// (first - 1, newest + 1) never overflows.
bool usableSeq(std::int64_t seq) { return seq >= 0 && seq < (std::int64_t{1} << 53); }

}  // namespace

Recorder::Recorder(std::unique_ptr<recording::McapWriter> out, std::string client_id, RecorderOptions o)
    : out_(std::move(out)), client_id_(std::move(client_id)), o_(o) {
  prepare();
}

// The schemas, the events' channel, every session's channels and scenario
// and the file's own metadata, in the current file (the first, or a new
// part after rotate()).
void Recorder::prepare() {
  state_schema_ = out_->addSchema("groundsim.state", "jsonschema", stateSchema());
  car_schema_ = out_->addSchema("groundsim.car_state", "jsonschema", carStateSchema());
  contact_schema_ = out_->addSchema("groundsim.contact_state", "jsonschema", contactStateSchema());
  event_schema_ = out_->addSchema("groundsim.event", "jsonschema", eventSchema());
  drive_schema_ = out_->addSchema("groundsim.drive", "jsonschema", driveSchema());
  controls_schema_ = out_->addSchema("groundsim.controls", "jsonschema", controlsSchema());
  applied_schema_ = out_->addSchema("groundsim.applied", "jsonschema", appliedSchema());
  events_.events_ch = out_->addChannel(event_schema_, "/events", "json",
                                       {{"stream", "server-wide events of no recorded session"}});
  raw_channels_.clear();
  // what the times mean, for any reader
  out_->metadata("groundsim", {{"log_time", "simulation time of the session (event: its session's, 0 without one)"},
                               {"sequence", "state_t.seq (events: event_t.seq), modulo 2^32"},
                               {"recorder", client_id_},
                               {"json_precision", precisionName()},
                               {"part", std::to_string(part_)}});
  for (auto& [id, s] : sessions_) {
    channels(s);
    if (!s.scenario.empty()) out_->attach("scenario/" + id + ".json", "application/json", 0, s.scenario);
    for (const auto& [name, bytes] : s.assets) out_->attach("assets/" + id + "/" + name, "application/octet-stream", 0, *bytes);
  }
}

void Recorder::channels(Stream& s) {
  const std::map<std::string, std::string> meta{{"session_id", s.id}};
  s.state_ch = out_->addChannel(state_schema_, "/" + s.id + "/state", "json", meta);
  s.car_ch = out_->addChannel(car_schema_, "/" + s.id + "/car_state", "json", meta);
  s.contact_ch = out_->addChannel(contact_schema_, "/" + s.id + "/contact", "json", meta);
  s.events_ch = out_->addChannel(event_schema_, "/" + s.id + "/events", "json", meta);
  s.drive_ch = out_->addChannel(drive_schema_, "/" + s.id + "/drive", "json", meta);
  s.controls_ch = out_->addChannel(controls_schema_, "/" + s.id + "/controls", "json", meta);
  s.applied_ch = out_->addChannel(applied_schema_, "/" + s.id + "/applied", "json", meta);
}

void Recorder::rotate(std::unique_ptr<recording::McapWriter> next) {
  writeLedgers();
  out_->close();
  out_ = std::move(next);
  ++part_;
  prepare();
}

std::uint64_t Recorder::bytesWritten() const { return out_->bytesWritten(); }

Recorder::~Recorder() {
  try {
    finish();
  } catch (...) {
  }
}

Recorder::Stream& Recorder::stream(const std::string& session) { return sessions_.at(session); }

void Recorder::add(const std::string& session, bool created) {
  if (auto it = sessions_.find(session); it != sessions_.end()) {
    if (created) it->second.ledger.oweFrom(0);
    return;
  }
  Stream& s = sessions_[session];
  s.id = session;
  s.group = static_cast<int>(sessions_.size());
  channels(s);
  if (created) s.ledger.owe(0);
}

void Recorder::addAsset(const std::string& session, const std::string& name, std::shared_ptr<const std::string> bytes) {
  auto it = sessions_.find(session);
  if (it == sessions_.end() || !bytes) return;
  out_->attach("assets/" + session + "/" + name, "application/octet-stream", 0, *bytes);
  it->second.assets.emplace_back(name, std::move(bytes));
}

std::uint16_t Recorder::rawChannel(const std::string& lcm_channel) {
  auto it = raw_channels_.find(lcm_channel);
  if (it != raw_channels_.end()) return it->second;
  const std::uint16_t id = out_->addChannel(0, "lcm/" + lcm_channel, "lcm", {{"lcm_channel", lcm_channel}});
  raw_channels_.emplace(lcm_channel, id);
  return id;
}

void Recorder::write(Stream& s, std::uint16_t channel, std::int64_t seq, std::int64_t utime, const std::string& json,
                     const std::string& lcm_channel, const std::uint8_t* data, int size) {
  const auto sequence = static_cast<std::uint32_t>(seq);
  out_->write(channel, sequence, ns(utime), ns(utime), json, s.group);
  if (o_.raw)
    out_->write(rawChannel(lcm_channel), sequence, ns(utime), ns(utime),
                std::string_view(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size)), s.group);
}

bool Recorder::fencedOff(Stream& s, std::int64_t epoch, std::int64_t seq) {
  if (epoch >= s.epoch) {
    if (epoch > s.epoch && s.epoch > 0) s.moved_at = s.top;  // what a new owner publishes up to here is re-simulated
    if (epoch > s.epoch || seq < s.epoch_from) s.epoch_from = seq;
    s.epoch = epoch;
    return false;
  }
  if (seq < s.epoch_from) return false;  // published before the move
  if (s.fenced++ == 0)
    std::fprintf(stderr, "record: %s: a message of epoch %lld after epoch %lld (a fenced owner's): not written, "
                         "counted in the ledger's fenced_count\n",
                 s.id.c_str(), static_cast<long long>(epoch), static_cast<long long>(s.epoch));
  return true;
}

template <class Msg>
void Recorder::companion(Stream& s, Ledger& l, std::uint16_t ch, const Msg& m, const std::string& channel,
                         const std::uint8_t* data, int size, bool repaired) {
  if (fencedOff(s, m.epoch, m.seq)) return;
  // the first heard starts its ledger where the state's did
  if (!l.started() && s.ledger.started()) l.owe(std::min(s.ledger.first(), m.seq));
  if (l.arrive(m.seq, repaired)) write(s, ch, m.seq, m.utime, toJson(m), channel, data, size);
}

bool Recorder::handle(const std::string& channel, const std::uint8_t* data, int size, bool repaired) {
  if (startsWith(channel, net::kStatePrefix)) return handleState(channel, data, size, repaired);
  if (startsWith(channel, net::kCarStatePrefix))
    return handleCompanion<groundsim::car_state_t>("groundsim.car_state_t", &Stream::car, &Stream::car_ch, channel,
                                                   data, size, repaired);
  if (startsWith(channel, net::kContactPrefix))
    return handleCompanion<groundsim::contact_state_t>("groundsim.contact_state_t", &Stream::contact,
                                                       &Stream::contact_ch, channel, data, size, repaired);
  if (startsWith(channel, net::kAppliedPrefix)) return handleApplied(channel, data, size, repaired);
  if (channel == net::kEventChannel) return handleEvent(channel, data, size, repaired);
  if (channel == net::kDriveChannel || channel == net::kControlsChannel) return handleCommand(channel, data, size);
  if (channel == net::kScenarioChannel) return handleScenario(data, size);
  return true;
}

bool Recorder::handleState(const std::string& channel, const std::uint8_t* data, int size, bool repaired) {
  groundsim::state_t m;
  if (!net::decodeMessage(data, size, m, "groundsim.state_t").ok() || !usableSeq(m.seq)) return false;
  auto it = sessions_.find(m.session_id);
  if (it == sessions_.end()) return true;
  Stream& s = it->second;
  if (fencedOff(s, m.epoch, m.seq)) return true;
  if (!s.ledger.arrive(m.seq, repaired)) {
    if (m.seq <= s.moved_at) ++s.resimulated;
    return true;
  }
  s.top = std::max(s.top, m.seq);
  // the frame's other messages follow the state: owed up to the one before
  if (s.car.started()) s.car.reach(m.seq - 1);
  if (s.contact.started()) s.contact.reach(m.seq - 1);
  if (m.status >= groundsim::state_t::STATUS_FINISHED) {
    s.ended = true;
    if (!s.end_frames.count(m.seq)) s.end_owed.try_emplace(m.seq, Gap{});
  }
  appliedOwed(s);
  if (!repaired && m.seq > s.live_seq) {
    s.live_seq = m.seq;
    s.live_utime = m.utime;
  }
  write(s, s.state_ch, m.seq, m.utime, toJson(m), channel, data, size);
  return true;
}

template <class Msg>
bool Recorder::handleCompanion(const char* type, Ledger Stream::*ledger, std::uint16_t Stream::*ch,
                               const std::string& channel, const std::uint8_t* data, int size, bool repaired) {
  Msg m;
  if (!net::decodeMessage(data, size, m, type).ok() || !usableSeq(m.seq)) return false;
  auto it = sessions_.find(m.session_id);
  if (it != sessions_.end()) companion(it->second, it->second.*ledger, it->second.*ch, m, channel, data, size, repaired);
  return true;
}

bool Recorder::handleApplied(const std::string& channel, const std::uint8_t* data, int size, bool repaired) {
  groundsim::applied_t m;
  if (!net::decodeMessage(data, size, m, "groundsim.applied_t").ok() || !usableSeq(m.seq) || !usableSeq(m.frame_seq))
    return false;
  auto it = sessions_.find(m.session_id);
  if (it == sessions_.end()) return true;
  Stream& s = it->second;
  if (fencedOff(s, m.epoch, m.frame_seq)) return true;
  if (!s.applied.started()) s.applied.owe(s.ledger.started() && s.ledger.first() == 0 ? 0 : m.seq);
  if (m.kind == groundsim::applied_t::KIND_END) {
    s.end_frames.insert(m.frame_seq);
    s.end_owed.erase(m.frame_seq);
    s.end_missing.erase(m.frame_seq);
  }
  if (m.seq < s.applied.first()) return true;  // before the recording
  if (!s.applied.arrive(m.seq, repaired)) return true;
  s.applied_frame[m.seq] = m.frame_seq;
  write(s, s.applied_ch, m.seq, m.utime, toJson(m), channel, data, size);
  return true;
}

bool Recorder::handleEvent(const std::string& channel, const std::uint8_t* data, int size, bool repaired) {
  groundsim::event_t m;
  if (!net::decodeMessage(data, size, m, "groundsim.event_t").ok() || !usableSeq(m.seq)) return false;
  if (!events_.ledger.arrive(m.seq, repaired)) return true;
  // a session's events go with it; the others (no session, or one not
  // recorded, e.g. a create refused, or an event heard before the
  // session's first state) into /events, so the stream is whole
  auto it = sessions_.find(m.session_id);
  if (it != sessions_.end()) write(it->second, it->second.events_ch, m.seq, m.utime, toJson(m), channel, data, size);
  else write(events_, events_.events_ch, m.seq, m.utime, toJson(m), channel, data, size);
  return true;
}

// players' commands: written as heard, at the session's newest state
// time, never with their token (and never as raw bytes, which hold it)
bool Recorder::handleCommand(const std::string& channel, const std::uint8_t* data, int size) {
  std::string session, json;
  std::int64_t seq = 0;
  const bool drive = channel == net::kDriveChannel;
  groundsim::drive_t d;
  groundsim::controls_t c;
  if (drive ? !net::decodeMessage(data, size, d, "groundsim.drive_t").ok()
            : !net::decodeMessage(data, size, c, "groundsim.controls_t").ok())
    return false;
  session = drive ? d.session_id : c.session_id;
  auto it = sessions_.find(session);
  if (it == sessions_.end()) return true;
  Stream& s = it->second;
  json = drive ? toJson(d, s.live_seq) : toJson(c, s.live_seq);
  seq = drive ? d.seq : c.seq;
  out_->write(drive ? s.drive_ch : s.controls_ch, static_cast<std::uint32_t>(seq), ns(s.live_utime),
              ns(s.live_utime), json, s.group);
  return true;
}

bool Recorder::handleScenario(const std::uint8_t* data, int size) {
  groundsim::scenario_t m;
  if (!net::decodeMessage(data, size, m, "groundsim.scenario_t").ok()) return false;
  auto it = sessions_.find(m.session_id);
  if (it == sessions_.end() || !it->second.scenario.empty()) return true;
  // kept (a few kB) so that every part of a rotated recording holds it
  it->second.scenario = m.scenario_json;
  out_->attach("scenario/" + m.session_id + ".json", "application/json", ns(m.utime), m.scenario_json);
  return true;
}

bool Recorder::onDatagram(const std::string& channel, const std::uint8_t* data, int size) {
  counts_.live_bytes += size;
  const bool ok = handle(channel, data, size, false);
  if (!ok) ++counts_.undecodable;
  return ok;
}

SeqRanges Recorder::missing(const Stream& s) const {
  SeqRanges u;
  for (const Ledger* l : {&s.ledger, &s.car, &s.contact})
    for (const auto& [a, b] : l->missing().ranges()) u.add(a, b);
  return u;
}

void Recorder::lose(Stream& s, std::int64_t first, std::int64_t last) {
  for (Ledger* l : {&s.ledger, &s.car, &s.contact}) l->lose(first, last);
  for (auto it = s.asking.lower_bound(first); it != s.asking.end() && it->first <= last;) it = s.asking.erase(it);
}

void Recorder::onResent(const groundsim::resent_t& m, Clock::time_point now) {
  Stream* s = nullptr;
  if (m.stream == groundsim::resend_t::STREAM_EVENTS) s = &events_;
  else if (auto it = sessions_.find(m.session_id); it != sessions_.end()) s = &it->second;
  if (!s) return;
  switch (m.status) {
    case groundsim::resent_t::STATUS_OK:
      counts_.resent_bytes += m.size;
      if (!handle(m.channel, m.data.data(), static_cast<int>(m.data.size()), true)) ++counts_.undecodable;
      break;
    case groundsim::resent_t::STATUS_GONE:
      std::fprintf(stderr, "record: %s: seq %lld..%lld no longer held by the server: lost\n",
                   s->id.empty() ? "events" : s->id.c_str(), static_cast<long long>(m.seq),
                   static_cast<long long>(m.last_seq));
      lose(*s, m.seq, m.last_seq);
      break;
    case groundsim::resent_t::STATUS_UNKNOWN_SESSION:
      std::fprintf(stderr, "record: %s: the server holds nothing of it: seq %lld..%lld lost\n", s->id.c_str(),
                   static_cast<long long>(m.seq), static_cast<long long>(m.last_seq));
      lose(*s, m.seq, m.last_seq < 0 ? INT64_MAX : m.last_seq);
      break;
    case groundsim::resent_t::STATUS_ELSEWHERE:
      // published by an earlier owner (the session moved): that server
      // answers with what it sent once it hears the next ask; the gap keeps
      // its schedule and is lost only when its asks are spent (a range not
      // asked for is ignored: nothing the network sends grows the state)
      if (auto gap = s->asking.find(m.seq); gap != s->asking.end() && !gap->second.elsewhere) {
        gap->second.elsewhere = true;
        std::fprintf(stderr, "record: %s: seq %lld..%lld published by an earlier owner: asked of it again\n",
                     s->id.c_str(), static_cast<long long>(m.seq), static_cast<long long>(m.last_seq));
      }
      break;
    case groundsim::resent_t::STATUS_LIMITED:
      // over our rate: ask again soon, without spending an ask
      for (auto& [first, gap] : s->asking)
        if (first <= (m.last_seq < 0 ? INT64_MAX : m.last_seq)) {
          gap.due = now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o_.limited_retry_s));
          gap.asks = std::max(0, gap.asks - 1);
        }
      break;
    default:
      break;
  }
}

void Recorder::onHeartbeat(const std::string& session, std::int64_t last_seq, bool final, Clock::time_point) {
  auto it = sessions_.find(session);
  if (it == sessions_.end() || !usableSeq(last_seq)) return;
  Stream& s = it->second;
  // listed before anything was heard: what it published so far came before
  // the recording
  if (!s.ledger.started()) s.ledger.owe(last_seq + 1);
  s.ledger.reach(last_seq);
  if (s.car.started()) s.car.reach(last_seq);
  if (s.contact.started()) s.contact.reach(last_seq);
  if (final) s.ended = true;
}

void Recorder::ask(Stream& s, std::int8_t kind, Clock::time_point now, std::vector<groundsim::resend_t>& out) {
  const SeqRanges u = missing(s);
  // forget gaps that were filled or split
  for (auto it = s.asking.begin(); it != s.asking.end();)
    it = u.ranges().count(it->first) ? std::next(it) : s.asking.erase(it);
  const auto after = [](double sec) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(sec));
  };
  for (const auto& [a, b] : u.ranges()) {
    auto [it, fresh] = s.asking.try_emplace(a, Gap{now + after(o_.first_ask_s), 0});
    Gap& g = it->second;
    if (g.due > now) continue;
    if (g.asks >= o_.asks) {
      std::fprintf(stderr, "record: %s: seq %lld..%lld never came after %d asks: lost\n",
                   s.id.empty() ? "events" : s.id.c_str(), static_cast<long long>(a), static_cast<long long>(b), g.asks);
      for (Ledger* l : {&s.ledger, &s.car, &s.contact}) l->lose(a, b);
      s.asking.erase(it);
      continue;
    }
    groundsim::resend_t r{};
    r.seq = request_seq_++;
    r.client_id = client_id_;
    r.stream = kind;
    r.session_id = s.id;
    r.from_seq = a;
    r.to_seq = std::min(b, a + o_.max_ask - 1);
    out.push_back(r);
    ++counts_.asked;
    g.due = now + after(o_.retry_s * static_cast<double>(1 << std::min(g.asks, 10)));
    ++g.asks;
  }
}

void Recorder::appliedOwed(Stream& s) {
  // a session recorded from its first state owes its log from entry 0
  if (!s.applied.started() && s.ledger.started() && s.ledger.first() == 0) s.applied.owe(0);
}

// Missing entries of the applied-command log are asked for as the frames
// they were kept with: from the frame of the entry before the gap to the
// frame of the entry after it (the states among them come again and are
// dropped as duplicates). An ending frame without its END entry is asked
// for again alone.
void Recorder::askApplied(Stream& s, Clock::time_point now, std::vector<groundsim::resend_t>& out) {
  const auto after = [](double sec) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(sec));
  };
  const auto request = [&](std::int64_t from, std::int64_t to) {
    groundsim::resend_t r{};
    r.seq = request_seq_++;
    r.client_id = client_id_;
    r.stream = groundsim::resend_t::STREAM_SESSION;
    r.session_id = s.id;
    r.from_seq = std::max<std::int64_t>(0, from);
    r.to_seq = std::max(r.from_seq, std::min(to, r.from_seq + o_.max_ask - 1));
    out.push_back(r);
    ++counts_.asked;
  };
  const auto due = [&](Gap& g) {
    if (g.due == Clock::time_point{}) g.due = now + after(o_.first_ask_s);
    return g.due <= now;
  };
  const auto next = [&](Gap& g) {
    g.due = now + after(o_.retry_s * static_cast<double>(1 << std::min(g.asks, 10)));
    ++g.asks;
  };
  const SeqRanges& u = s.applied.missing();
  for (auto it = s.asking_applied.begin(); it != s.asking_applied.end();)
    it = u.ranges().count(it->first) ? std::next(it) : s.asking_applied.erase(it);
  for (const auto& [a, b] : u.ranges()) {
    Gap& g = s.asking_applied[a];
    if (!due(g)) continue;
    if (g.asks >= o_.asks) {
      std::fprintf(stderr, "record: %s: applied commands %lld..%lld never came after %d asks: lost\n", s.id.c_str(),
                   static_cast<long long>(a), static_cast<long long>(b), g.asks);
      s.applied.lose(a, b);
      s.asking_applied.erase(a);
      continue;
    }
    auto before = s.applied_frame.lower_bound(a);
    const std::int64_t from = before == s.applied_frame.begin() ? std::max<std::int64_t>(0, s.ledger.first())
                                                                 : std::prev(before)->second;
    auto later = s.applied_frame.upper_bound(b);
    const std::int64_t to = later == s.applied_frame.end() ? std::max(from, s.ledger.newest()) : later->second;
    request(from, to);
    next(g);
  }
  for (auto it = s.end_owed.begin(); it != s.end_owed.end();) {
    Gap& g = it->second;
    if (!due(g)) {
      ++it;
      continue;
    }
    if (g.asks >= o_.asks) {
      std::fprintf(stderr, "record: %s: the applied-command log's end entry with frame %lld never came: its tail "
                   "may be incomplete\n", s.id.c_str(), static_cast<long long>(it->first));
      s.end_missing.insert(it->first);
      it = s.end_owed.erase(it);
      continue;
    }
    request(it->first, it->first);
    next(g);
    ++it;
  }
}

std::vector<groundsim::resend_t> Recorder::requests(Clock::time_point now) {
  std::vector<groundsim::resend_t> out;
  for (auto& [id, s] : sessions_) {
    ask(s, groundsim::resend_t::STREAM_SESSION, now, out);
    askApplied(s, now, out);
  }
  ask(events_, groundsim::resend_t::STREAM_EVENTS, now, out);
  return out;
}

std::vector<groundsim::resend_t> Recorder::tailRequests(Clock::time_point) {
  std::vector<groundsim::resend_t> out;
  for (auto& [id, s] : sessions_) {
    if (!s.ledger.started()) continue;
    groundsim::resend_t r{};
    r.seq = request_seq_++;
    r.client_id = client_id_;
    r.stream = groundsim::resend_t::STREAM_SESSION;
    r.session_id = id;
    r.from_seq = s.ledger.newest() + 1;
    r.to_seq = -1;
    out.push_back(r);
    ++counts_.asked;
  }
  return out;
}

bool Recorder::repairing() const {
  for (const auto& [id, s] : sessions_)
    if (missing(s).count() > 0 || s.applied.missing().count() > 0 || !s.end_owed.empty()) return true;
  return events_.ledger.missing().count() > 0;
}

bool Recorder::ended(const std::string& session) const {
  auto it = sessions_.find(session);
  return it != sessions_.end() && it->second.ended;
}

bool Recorder::allEnded() const {
  if (sessions_.empty()) return false;
  for (const auto& [id, s] : sessions_)
    if (!s.ended) return false;
  return true;
}

Recorder::Totals Recorder::totals() const {
  Totals t = counts_;
  const auto add = [&t](const Ledger& l) {
    t.received += l.received().count();
    t.repaired += l.repaired().count();
    t.lost += l.lost().count();
    t.missing += l.missing().count();
    t.duplicates += l.duplicates();
  };
  for (const auto& [id, s] : sessions_) {
    add(s.ledger);
    add(s.car);
    add(s.contact);
    add(s.applied);
  }
  add(events_.ledger);
  return t;
}

std::vector<std::string> Recorder::report() const {
  std::vector<std::string> lines;
  for (const auto& [id, s] : sessions_) {
    std::string line = id + " states: " + s.ledger.summary();
    if (s.car.started()) line += "; car states: " + s.car.summary();
    if (s.contact.started()) line += "; contacts: " + s.contact.summary();
    if (s.applied.started()) line += "; applied commands: " + s.applied.summary();
    if (!s.end_missing.empty()) line += "; the applied log's end entry missing";
    if (s.resimulated > 0 || s.fenced > 0)
      line += "; " + std::to_string(s.resimulated) + " states re-simulated after a move (epoch " +
              std::to_string(s.epoch) + "; the first publication kept), " + std::to_string(s.fenced) +
              " messages of a fenced owner dropped";
    lines.push_back(line + (s.ended ? "; ended" : ""));
  }
  lines.push_back("events: " + events_.ledger.summary());
  return lines;
}

void Recorder::finish() {
  if (finished_) return;
  finished_ = true;
  for (auto& [id, s] : sessions_) {
    for (Ledger* l : {&s.ledger, &s.car, &s.contact, &s.applied}) l->loseMissing();
    for (const auto& [frame, gap] : s.end_owed) s.end_missing.insert(frame);
    s.end_owed.clear();
  }
  events_.ledger.loseMissing();
  writeLedgers();
  out_->close();
}

// Each stream's ledger so far into the current file (a part of a rotated
// recording holds the ledgers as they stood when it was closed: missing
// seqs may still be repaired, into a later part).
void Recorder::writeLedgers() {
  const auto ledger = [](const Ledger& l, const std::string& prefix, std::map<std::string, std::string>& kv) {
    kv[prefix + "first"] = std::to_string(l.first());
    kv[prefix + "newest"] = std::to_string(l.newest());
    kv[prefix + "received"] = l.received().text(100000);
    kv[prefix + "repaired"] = l.repaired().text(100000);
    kv[prefix + "lost"] = l.lost().text(100000);
    kv[prefix + "received_count"] = std::to_string(l.received().count());
    kv[prefix + "repaired_count"] = std::to_string(l.repaired().count());
    kv[prefix + "lost_count"] = std::to_string(l.lost().count());
    kv[prefix + "missing"] = l.missing().text(100000);
  };
  for (const auto& [id, s] : sessions_) {
    std::map<std::string, std::string> kv{{"session_id", id}, {"ended", s.ended ? "true" : "false"},
                                          {"epoch", std::to_string(s.epoch)}, {"fenced_count", std::to_string(s.fenced)},
                                          {"state_resimulated_count", std::to_string(s.resimulated)}};
    ledger(s.ledger, "state_", kv);
    if (s.car.started()) ledger(s.car, "car_state_", kv);
    if (s.contact.started()) ledger(s.contact, "contact_", kv);
    if (s.applied.started()) ledger(s.applied, "applied_", kv);
    if (!s.end_missing.empty()) {
      SeqRanges r;
      for (std::int64_t f : s.end_missing) r.add(f, f);
      kv["applied_end_missing"] = r.text(100000);  // ending frames whose END entry never came
    }
    out_->metadata("ledger/" + id, kv);
  }
  std::map<std::string, std::string> kv;
  ledger(events_.ledger, "event_", kv);
  out_->metadata("ledger/events", kv);
}

}  // namespace groundsim::record
