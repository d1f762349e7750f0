#include "lcm_server.hpp"

#include <algorithm>

#include <groundsim/replica_t.hpp>

#include "fleet_node.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <groundsim/asset_want_t.hpp>
#include <groundsim/resend_t.hpp>
#include <groundsim/resent_t.hpp>
#include <groundsim/scenario_t.hpp>

#include "convert.hpp"
#include "input_checks.hpp"
#include "latency_trace.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/vec_parts.hpp"
#include "session/token.hpp"

namespace groundsim::net {
namespace {

std::int64_t wallMicros() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

using input_checks::badId;

}  // namespace

LcmServer::LcmServer(const std::string& url, const session::ServiceConfig& cfg, bool verbose)
    : url_(withReceiveBuffer(url)), verbose_(verbose), lcm_(url_), server_id_(session::randomHex(8)) {
  if (!lcm_.good())
    throw std::runtime_error("cannot open LCM URL " + url_ +
                             " (no multicast route? e.g. `ip route add 224.0.0.0/4 dev lo`)");
  service_ = std::make_unique<session::SessionService>(cfg, *this);
  // Requests and drives from many clients may arrive in bursts while this
  // thread is busy: a deep queue instead of LCM's silent 30.
  // (asset parts come in bursts of up to 2 MiB, protocol/assets_client.cpp)
  for (const char* channel :
       {kRequestChannel, kDriveChannel, kControlsChannel, kVecRequestChannel, kAssetChannel, kResendChannel})
    lcm_.subscribe(channel, &LcmServer::onDatagram, this)->setQueueCapacity(kDeepQueue);
}

LcmServer::~LcmServer() { service_.reset(); }

template <class T>
void LcmServer::publish(const std::string& channel, const T& msg, const std::string* keep_session,
                        std::int64_t keep_seq, bool send) {
  // encode outside the lock; one reusable buffer per thread
  static thread_local std::vector<std::uint8_t> buf;
  const int size = msg.getEncodedSize();
  if (buf.size() < static_cast<size_t>(size)) buf.resize(size);
  if (msg.encode(buf.data(), 0, size) < 0) return;
  std::lock_guard<std::mutex> lk(publish_mutex_);
  if (send) lcm_.publish(channel, buf.data(), static_cast<unsigned>(size));
  if (keep_seq < 0) return;
  if (keep_session) ring_.addFrame(*keep_session, keep_seq, channel, buf.data(), static_cast<std::size_t>(size), send);
  else ring_.addEvent(keep_seq, channel, buf.data(), static_cast<std::size_t>(size));
}

void LcmServer::setResendLimits(const ResendLimits& limits) {
  std::lock_guard<std::mutex> lk(publish_mutex_);
  ring_ = ResendRing(limits);
}

ResendRing::Stats LcmServer::resendStats() {
  std::lock_guard<std::mutex> lk(publish_mutex_);
  return ring_.stats();
}

bool LcmServer::mayPublish(const std::string& session_id) const {
  return !fleet_ || session_id.empty() || fleet_->mayPublish(session_id);
}

LcmServer::Outlet LcmServer::outlet(const std::string& session_id) const {
  if (mayPublish(session_id)) return Outlet::Send;
  // fenced, not known to be taken over: kept for re-requests, which a
  // recorder makes once the lease is back and the session still ours (a
  // leader election of the fleet's etcd costs it no message)
  return fleet_->fenced() && fleet_->holds(session_id) ? Outlet::Keep : Outlet::Drop;
}

void LcmServer::publishState(const session::Frame& f) {
  const Outlet o = outlet(f.session_id);
  if (o == Outlet::Drop) return;
  const bool send = o == Outlet::Send;
  try {
    publish(stateChannel(f.session_id), toMessage(f), &f.session_id, f.seq, send);
    if (send) {
      ++frames_;
      if (LatencyTrace::on())
        LatencyTrace::line("spub %s %lld %lld %lld %lld", f.session_id.c_str(), static_cast<long long>(f.seq),
                           static_cast<long long>(LatencyTrace::nowUs()),
                           static_cast<long long>(LatencyTrace::us(f.drive_received)),
                           static_cast<long long>(LatencyTrace::us(f.drive_applied)));
    }
    if (!f.cars.empty()) publish(carStateChannel(f.session_id), toCarMessage(f), &f.session_id, f.seq, send);
    if (f.contacts) publish(contactChannel(f.session_id), toContactMessage(f), &f.session_id, f.seq, send);
  } catch (const std::exception& e) {
    ++errors_;
    std::fprintf(stderr, "groundsim-server: cannot publish a state of %s: %s\n", f.session_id.c_str(), e.what());
  }
}

void LcmServer::publishApplied(const session::Applied& a) {
  const Outlet o = outlet(a.session_id);
  if (o == Outlet::Drop) return;
  try {
    publish(appliedChannel(a.session_id), toMessage(a), &a.session_id, a.frame_seq, o == Outlet::Send);
  } catch (const std::exception& e) {
    ++errors_;
    std::fprintf(stderr, "groundsim-server: cannot publish an applied command of %s: %s\n", a.session_id.c_str(),
                 e.what());
  }
}

void LcmServer::publishReply(const session::Reply& r) {
  try {
    // the scenario first: a viewer that asked for it has it when the reply comes
    if (r.ok && !r.scenario_json.empty()) {
      groundsim::scenario_t m{};
      m.utime = toUtime(r.t);
      m.seq = scenario_seq_++;
      m.request_id = r.op == session::Op::Scenario ? r.request_id : 0;
      m.client_id = r.op == session::Op::Scenario ? r.client_id : "";
      m.session_id = r.session_id;
      m.name = r.scenario_name;
      m.scenario_json = r.scenario_json;
      publish(kScenarioChannel, m);
    }
    groundsim::reply_t m = toMessage(r, reply_seq_++);
    for (auto& s : m.sessions) if (s.server_id.empty()) s.server_id = server_id_;
    publish(kReplyChannel, m);
    if (r.ok && (r.op == session::Op::Create || r.op == session::Op::Stop)) beat_soon_ = true;
  } catch (const std::exception& e) {
    ++errors_;
    std::fprintf(stderr, "groundsim-server: cannot publish a reply: %s\n", e.what());
  }
}

void LcmServer::publishVecReply(const session::VecReply& r) {
  try {
    groundsim::vec_reply_t whole = toMessage(r, 0);
    whole.utime = wallMicros();
    for (auto& s : whole.sessions) if (s.server_id.empty()) s.server_id = server_id_;
    // each part one datagram; a client accounts for each (protocol/vec_parts.hpp)
    for (groundsim::vec_reply_t& part : splitVecReply(whole)) {
      part.seq = vec_seq_++;
      publish(kVecReplyChannel, part);
    }
    if (LatencyTrace::on())
      LatencyTrace::line("vrep %s %lld %d %lld", whole.client_id.c_str(), static_cast<long long>(whole.request_id),
                         whole.ok ? 1 : 0, static_cast<long long>(LatencyTrace::nowUs()));
  } catch (const std::exception& e) {
    ++errors_;
    std::fprintf(stderr, "groundsim-server: cannot publish a vec reply: %s\n", e.what());
  }
}

void LcmServer::publishAssetWant(const session::AssetWant& w) {
  try {
    groundsim::asset_want_t m{};
    m.utime = wallMicros();
    m.seq = want_seq_++;
    m.request_id = w.request_id;
    m.client_id = w.client_id;
    m.name = w.missing.ref.name;
    m.sha256 = w.missing.ref.sha256;
    m.size = static_cast<std::int64_t>(w.missing.ref.size);
    m.nparts = w.missing.nparts;
    m.missing = w.missing.parts;
    m.nmissing = static_cast<std::int32_t>(m.missing.size());
    publish(kAssetWantChannel, m);
  } catch (const std::exception& e) {
    ++errors_;
    std::fprintf(stderr, "groundsim-server: cannot publish an asset want: %s\n", e.what());
  }
}

void LcmServer::publishEvent(const session::Event& e) try {
  if (!mayPublish(e.session_id)) return;
  const std::int64_t seq = event_seq_++;
  groundsim::event_t m = toMessage(e, seq);
  m.server_id = server_id_;
  publish(kEventChannel, m, nullptr, seq);
  if (e.severity == session::Severity::Info) {
    if (verbose_)
      std::fprintf(stderr, "groundsim-server: %s%s%s\n", e.session_id.c_str(), e.session_id.empty() ? "" : ": ",
                   printable(e.reason, 2000).c_str());
    return;
  }
  ++errors_;
  if (e.code == session::ErrorCode::Overrun) ++overruns_;
  if (verbose_)
    std::fprintf(stderr, "groundsim-server: %s %d%s%s%s%s: %s\n",
                 e.severity == session::Severity::Warning ? "warning" : "error", static_cast<int>(e.code),
                 e.session_id.empty() ? "" : " session ", e.session_id.c_str(),
                 e.channel.empty() ? "" : " on ", e.channel.c_str(), printable(e.reason, 2000).c_str());
} catch (const std::exception& x) {
  ++errors_;
  std::fprintf(stderr, "groundsim-server: cannot publish an event: %s\n", x.what());
}

static_assert(static_cast<std::int8_t>(ResendRing::Status::Ok) == groundsim::resent_t::STATUS_OK &&
              static_cast<std::int8_t>(ResendRing::Status::Gone) == groundsim::resent_t::STATUS_GONE &&
              static_cast<std::int8_t>(ResendRing::Status::Limited) == groundsim::resent_t::STATUS_LIMITED &&
              static_cast<std::int8_t>(ResendRing::Status::UnknownSession) ==
                  groundsim::resent_t::STATUS_UNKNOWN_SESSION &&
              static_cast<std::int8_t>(ResendRing::Status::Elsewhere) == groundsim::resent_t::STATUS_ELSEWHERE,
              "the ring's statuses are resent_t's");

// In a fleet each server keeps its own ring: the owner answers for a session
// (every server for its events), what it kept while fenced included. Every
// other server that holds some of the session answers with the messages it
// sent, so the frames an owner published before the session moved (its
// lease lost while a recorder's re-request was on its way) are still
// repaired; a fenced server answers only what it sent, and its kept frames
// go out once its lease is back and the session still its own.
ResendRing::Scope LcmServer::resendScope(const groundsim::resend_t& msg) {
  if (!fleet_) return ResendRing::Scope::Owner;
  if (fleet_->fenced()) return ResendRing::Scope::Published;
  if (msg.stream == groundsim::resend_t::STREAM_SESSION && !fleet_->answers(msg.session_id, [] {}))
    return ResendRing::Scope::Published;
  return ResendRing::Scope::Owner;
}

// A recorder's re-request: answered from the ring within the client's rate
// limit (resend_ring.hpp), on the client's own channel so other
// subscribers never see old messages again.
void LcmServer::handleResend(const std::string& channel, const void* data, int size) {
  groundsim::resend_t msg;
  if (!decoded(msg, "groundsim.resend_t", channel, data, size)) return;
  std::string why = badId("client_id", msg.client_id);
  if (why.empty() && msg.client_id.empty()) why = "client_id: empty (answers go to " + std::string(kResentPrefix) + "<client_id>)";
  if (why.empty()) why = badId("session_id", msg.session_id);
  if (why.empty() && msg.stream != groundsim::resend_t::STREAM_SESSION && msg.stream != groundsim::resend_t::STREAM_EVENTS)
    why = "stream: must be 1 (session) or 2 (events), got " + std::to_string(msg.stream);
  if (why.empty() && msg.stream == groundsim::resend_t::STREAM_SESSION && msg.session_id.empty())
    why = "session_id: empty for stream 1 (session)";
  if (why.empty() && msg.from_seq < 0) why = "from_seq: must be >= 0, got " + std::to_string(msg.from_seq);
  if (why.empty() && msg.to_seq < -1) why = "to_seq: must be >= -1 (-1: up to the newest), got " + std::to_string(msg.to_seq);
  if (!why.empty()) return service_->reportBadInput(session::ErrorCode::BadRequest, channel, "resend: " + why);
  const ResendRing::Scope scope = resendScope(msg);
  const std::string session = msg.stream == groundsim::resend_t::STREAM_EVENTS ? "" : msg.session_id;
  std::vector<ResendRing::Message> answer;
  {
    std::lock_guard<std::mutex> lk(publish_mutex_);
    answer = ring_.answer(msg.client_id, session, msg.from_seq, msg.to_seq, scope);
  }
  const std::string out = kResentPrefix + msg.client_id;
  groundsim::resent_t r{};
  r.utime = wallMicros();
  r.request_seq = msg.seq;
  r.stream = msg.stream;
  r.session_id = msg.session_id;
  for (ResendRing::Message& m : answer) {
    r.seq = m.seq;
    r.last_seq = m.last_seq;
    r.status = static_cast<std::int8_t>(m.status);
    r.channel = m.channel;
    r.data.assign(m.bytes.begin(), m.bytes.end());
    r.size = static_cast<std::int32_t>(r.data.size());
    publish(out, r);
  }
}

void LcmServer::heartbeat() {
  {
    std::lock_guard<std::mutex> lk(publish_mutex_);
    ring_.expire(std::chrono::steady_clock::now());
  }
  const session::ServiceStatus st = service_->status();
  if (fleet_) {
    if (fleet_->fenced()) return;  // cut off from the fleet: silent
    fleet_->updateCapacity(st);
  }
  groundsim::server_status_t m;
  m.utime = wallMicros();
  m.seq = status_seq_++;
  m.server_id = server_id_;
  m.workers = st.workers;
  m.max_sessions = st.max_sessions;
  m.load = st.load;
  m.frames_published = frames_.load();
  m.requests_handled = inputs_.load();
  m.errors = errors_.load();
  // ended sessions too (final status, last seq): subscribers whose final
  // state was lost learn from here that the session ended and at which seq
  for (const auto& s : st.sessions) m.sessions.push_back(toMessage(s, false));
  for (const auto& s : st.ended) m.sessions.push_back(toMessage(s, false));
  for (auto& s : m.sessions) if (s.server_id.empty()) s.server_id = server_id_;
  m.nsessions = static_cast<int32_t>(m.sessions.size());
  publish(kStatusChannel, m);
  Counters c;
  c.beat = true;
  c.workers = st.workers;
  c.max_sessions = st.max_sessions;
  c.load = st.load;
  for (const auto& s : st.sessions) {
    const int mode = static_cast<int>(s.mode) - 1;
    if (mode >= 0 && mode < 4) ++c.sessions_by_mode[mode];
  }
  std::lock_guard<std::mutex> lk(beat_mutex_);
  beat_ = c;
}

LcmServer::Counters LcmServer::counters() const {
  Counters c;
  {
    std::lock_guard<std::mutex> lk(beat_mutex_);
    c = beat_;
  }
  c.states_published = frames_.load();
  c.requests_handled = inputs_.load();
  c.errors = errors_.load();
  c.heartbeats = status_seq_.load();
  c.overrun_events = overruns_.load();
  c.standby_asks = ask_seq_.load();
  c.standby_repaired = applied_repaired_.load();
  if (fleet_) c.standby_sessions = static_cast<std::int64_t>(fleet_->standbyCount());
  return c;
}

const char* LcmServer::fleetTrouble() const {
  if (!fleet_) return nullptr;
  if (fleet_->fenced()) return "fenced";
  if (fleet_->draining() || drain_requested_.load()) return "draining";
  return nullptr;
}

void LcmServer::setFleet(FleetNode* fleet) {
  fleet_ = fleet;
  if (!fleet_) return;
  // what a standby keeps of the others' sessions, and the fleet's listings
  lcm_.subscribe(std::string(kReplicaPrefix) + ".*", &LcmServer::onFleet, this)->setQueueCapacity(kDeepQueue);
  lcm_.subscribe(std::string(kAppliedPrefix) + ".*", &LcmServer::onFleet, this)->setQueueCapacity(kDeepQueue);
  lcm_.subscribe(kStatusChannel, &LcmServer::onFleet, this)->setQueueCapacity(kDeepQueue);
  lcm_.subscribe(std::string(kStatePrefix) + ".*", &LcmServer::onFleet, this)->setQueueCapacity(kDeepQueue);
  // a standby's gap repair: the owner's resend ring answers as it answers a
  // recorder, on this server's own channel
  const std::string client_id = "fleet-" + server_id_;
  lcm_.subscribe(kResentPrefix + client_id, &LcmServer::onFleet, this)->setQueueCapacity(kDeepQueue);
  fleet_->setAskAgain([this, client_id](const std::string& session_id, std::int64_t from, std::int64_t to) {
    groundsim::resend_t r{};
    r.utime = wallMicros();
    r.seq = ask_seq_++;
    r.client_id = client_id;
    r.stream = groundsim::resend_t::STREAM_SESSION;
    r.session_id = session_id;
    r.from_seq = from;
    r.to_seq = to;
    publish(kResendChannel, r);
  });
}

void LcmServer::onFleet(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  try {
    handleFleet(channel, rbuf->data, static_cast<int>(rbuf->data_size));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundsim-server: fleet input on %s: %s\n", channel.c_str(), e.what());
  } catch (...) {
  }
}

// Other servers' output, heard as any subscriber hears it: undecodable
// datagrams are not answered (they are no request), only counted.
void LcmServer::handleFleet(const std::string& channel, const void* data, int size) {
  if (channel == kStatusChannel) {
    groundsim::server_status_t m;
    if (!decodeMessage(data, size, m, "groundsim.server_status_t").ok()) return void(++errors_);
    if (m.server_id == server_id_) return;
    std::vector<session::SessionInfo> list;
    for (const auto& s : m.sessions)
      if (s.status == static_cast<int8_t>(session::Status::Running) || s.status == static_cast<int8_t>(session::Status::Paused))
        list.push_back(fromMessage(s));
    for (auto& s : list) if (s.server_id.empty()) s.server_id = m.server_id;
    fleet_->onListing(m.server_id, std::move(list));
  } else if (channel.rfind(kReplicaPrefix, 0) == 0) {
    groundsim::replica_t m;
    if (!decodeMessage(data, size, m, "groundsim.replica_t").ok()) return void(++errors_);
    fleet_->onReplica(fromMessage(m), m.server_id);
  } else if (channel.rfind(kAppliedPrefix, 0) == 0) {
    groundsim::applied_t m;
    if (!decodeMessage(data, size, m, "groundsim.applied_t").ok()) return void(++errors_);
    fleet_->onApplied(fromMessage(m));
  } else if (channel.rfind(kStatePrefix, 0) == 0) {
    // only the head: how far the owner got (a standby needs no more)
    if (const auto h = peekState(data, size)) fleet_->onState(channel.substr(std::strlen(kStatePrefix)), h->seq, h->tick, h->epoch);
  } else if (channel.rfind(kResentPrefix, 0) == 0) {
    // what the owner sends again: only the applied entries are of use here
    groundsim::resent_t m;
    if (!decodeMessage(data, size, m, "groundsim.resent_t").ok()) return void(++errors_);
    if (m.status != groundsim::resent_t::STATUS_OK || m.channel.rfind(kAppliedPrefix, 0) != 0) return;
    ++applied_repaired_;
    handleFleet(m.channel, m.data.data(), static_cast<int>(m.data.size()));
  }
}

void LcmServer::publishReplica(const session::Replica& r) {
  if (r.kind != session::Replica::Kind::Released && !mayPublish(r.session_id)) return;
  try {
    groundsim::replica_t m = toMessage(r);
    m.utime = wallMicros();
    m.seq = replica_seq_++;
    m.server_id = server_id_;
    publish(replicaChannel(r.session_id), m);
  } catch (const std::exception& e) {
    ++errors_;
    std::fprintf(stderr, "groundsim-server: cannot publish a replica of %s: %s\n", r.session_id.c_str(), e.what());
  }
}

void LcmServer::run(const std::atomic<bool>& stop) {
  using namespace std::chrono;
  auto next_beat = steady_clock::now(), next_housekeeping = next_beat;
  const auto period = duration_cast<steady_clock::duration>(duration<double>(heartbeat_period_));
  const int wait_ms = std::clamp(static_cast<int>(heartbeat_period_ * 250), 10, 100);
  while (!stop.load() && !drain_requested_.load()) {
    // short timeout so that a signal is noticed promptly and beats keep their period
    if (lcm_.handleTimeout(wait_ms) < 0 && !stop.load()) {  // a signal interrupts the wait: not an error
      std::fprintf(stderr, "groundsim-server: LCM receive error on %s\n", url_.c_str());
      std::this_thread::sleep_for(milliseconds(100));
    }
    const auto now = steady_clock::now();
    if (now >= next_beat || beat_soon_.exchange(false)) {
      try {
        if (now >= next_housekeeping) {  // idle reclamation and the like: once a second is enough
          service_->housekeeping();
          next_housekeeping = now + seconds(1);
        }
        heartbeat();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "groundsim-server: heartbeat failed: %s\n", e.what());
      }
      next_beat = now + period;
    }
  }
  session::Event bye;
  bye.severity = session::Severity::Info;
  bye.code = session::ErrorCode::Shutdown;
  bye.reason = "server " + server_id_ + " stopping";
  publishEvent(bye);
  // in a fleet, a server that stops hands its sessions over first
  if (fleet_) fleet_->drain(std::chrono::seconds(5));
  service_->shutdown("server stopped");
  heartbeat();  // lists no sessions
}

}  // namespace groundsim::net
