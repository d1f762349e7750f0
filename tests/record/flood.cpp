// record_flood: a synthetic server for checking `groundsim record`'s
// accounting at rates the simulation cannot reach on a small machine
// (issue 23: 100 sessions x 2 kHz x 60 s with bursts). It publishes real
// encoded state_t on GROUNDSIM_STATE_<session> with seqs 0, 1, 2 ... per
// session, a heartbeat (server_status_t) each second listing every
// session's newest seq, and at the end each session's last frame: an
// applied_t END entry and a state with status FINISHED, as the server
// does. With --ring (the default) it keeps what it published in the
// server's own ResendRing (server/lcm/resend_ring.*, same limits) and
// answers resend_t as the server does, so repair is exercised.
//
// Rates: each session publishes --rate states per wall second; every
// --burst-every s, for --burst-s s, --burst-factor times that. Rounds
// publish one state of every session, so the sessions interleave. A
// publisher behind its schedule publishes as fast as it can (and says so
// in the report: scheduled against sent).
//
//   record_flood [--sessions N] [--rate HZ] [--duration S] [--burst-every S] [--burst-s S]
//                [--burst-factor F] [--no-ring] [--go FILE] [--report FILE] [--linger S] [--url URL]
//
// --go FILE: heartbeats start at once, the sessions once FILE exists (a
// recorder then sees them begin: seq 0 is owed). --report FILE: JSON with
// each session's sent count (seqs 0 .. sent-1) and "ring", written when
// the sessions end. It then goes on heartbeating and answering
// re-requests for --linger s, or until SIGINT/SIGTERM, and at exit writes
// the report again with "answers" (the re-requests and what they were
// answered with) and "resent": per session, the ranges of seqs the ring
// resent (status OK), which record_flood_check holds the ledger's
// repaired seqs against (issue 35: a repair the ring never sent is none).
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <groundsim/applied_t.hpp>
#include <groundsim/resend_t.hpp>
#include <groundsim/resent_t.hpp>
#include <groundsim/server_status_t.hpp>
#include <groundsim/state_t.hpp>

#include "lcm/resend_ring.hpp"
#include "protocol/channels.hpp"

namespace {

using Clock = std::chrono::steady_clock;
std::atomic<bool> g_stop{false};

std::int64_t wallMicros() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

struct Options {
  int sessions = 100;
  double rate = 2000, duration = 60, burst_every = 5, burst_s = 0.5, burst_factor = 4;
  bool ring = true;
  std::string go, report, url;
  double linger = 120;
};

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr, "record_flood: %s\n", why);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value of " + a).c_str());
      return argv[++i];
    };
    if (a == "--sessions") o.sessions = std::atoi(value().c_str());
    else if (a == "--rate") o.rate = std::atof(value().c_str());
    else if (a == "--duration") o.duration = std::atof(value().c_str());
    else if (a == "--burst-every") o.burst_every = std::atof(value().c_str());
    else if (a == "--burst-s") o.burst_s = std::atof(value().c_str());
    else if (a == "--burst-factor") o.burst_factor = std::atof(value().c_str());
    else if (a == "--no-ring") o.ring = false;
    else if (a == "--go") o.go = value();
    else if (a == "--report") o.report = value();
    else if (a == "--linger") o.linger = std::atof(value().c_str());
    else if (a == "--url") o.url = value();
    else usage(("unknown option " + a).c_str());
  }
  if (o.sessions < 1 || o.sessions > 1000 || !(o.rate > 0) || !(o.duration > 0) || !(o.burst_factor >= 1) ||
      o.burst_s < 0 || o.burst_every < 0)
    usage("bad option values");
  return o;
}

// States per session owed by wall time t: rate * t, plus (factor - 1) *
// rate for the time spent in bursts ([k E, k E + B) for k = 1, 2 ...).
double scheduled(const Options& o, double t) {
  double burst = 0;
  if (o.burst_every > 0 && o.burst_s > 0)
    for (double s = o.burst_every; s < t; s += o.burst_every) burst += std::min(o.burst_s, t - s);
  return o.rate * (t + (o.burst_factor - 1) * burst);
}

template <class T>
std::vector<std::uint8_t> encode(const T& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

struct Session {
  std::string id, channel;
  groundsim::state_t state;
  std::int64_t next = 0;  // seq of the next state
  bool finished = false;
};

// A plausible one-car state at seq n: a car driving a 40 m circle at 12 m/s.
void fill(groundsim::state_t& m, std::int64_t n, double dt, int index) {
  const double t = static_cast<double>(n) * dt, w = 12.0 / 40.0, ph = 0.1 * index + w * t;
  m.seq = n;
  m.t = t;
  m.utime = static_cast<std::int64_t>(std::llround(t * 1e6));
  m.tick = n;
  m.energy = 0.5 * 1500 * 144 + 0.01 * std::sin(t);
  auto& v = m.vehicles[0];
  v.utime = m.utime;
  v.position[0] = 40 * std::cos(ph);
  v.position[1] = 40 * std::sin(ph);
  v.position[2] = 0.45 + 0.002 * std::sin(9 * t);
  v.orientation[0] = std::cos(ph / 2 + 0.785);
  v.orientation[3] = std::sin(ph / 2 + 0.785);
  v.velocity[0] = -12 * std::sin(ph);
  v.velocity[1] = 12 * std::cos(ph);
  v.angular_velocity[2] = w;
  v.speed = 12;
  for (int k = 0; k < 4; ++k) {
    v.wheel_spin[k] = 40 + 0.3 * std::sin(t + k);
    v.normal_force[k] = 3600 + 150 * std::cos(2 * t + k);
    v.friction_force[k] = 700 + 40 * std::sin(3 * t + k);
    v.slip[k] = 0.05 + 0.01 * std::sin(5 * t + k);
    v.in_contact[k] = 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  // a deep socket buffer: its socket hears the whole stream, and re-requests among it
  lcm::LCM lcm(groundsim::net::withReceiveBuffer(o.url));
  if (!lcm.good()) usage("cannot open LCM (no multicast route?)");

  char server_id[64];
  std::snprintf(server_id, sizeof server_id, "flood-%d", static_cast<int>(getpid()));
  const double dt = 1.0 / o.rate;  // simulation time between states
  std::vector<Session> sessions(static_cast<std::size_t>(o.sessions));
  for (int i = 0; i < o.sessions; ++i) {
    Session& s = sessions[static_cast<std::size_t>(i)];
    char id[16];
    std::snprintf(id, sizeof id, "F1%06X", static_cast<unsigned>(0x5A0000 + i));
    s.id = id;
    s.channel = groundsim::net::stateChannel(s.id);
    groundsim::state_t& m = s.state;
    m.session_id = s.id;
    m.mode = 1;
    m.status = groundsim::state_t::STATUS_RUNNING;
    m.health = groundsim::state_t::HEALTH_OK;
    m.nvehicles = 1;
    m.vehicles.resize(1);
    m.vehicles[0].name = "sedan";
    m.vehicles[0].wheel_count = 4;
    m.epoch = 0;
    m.error_estimate = -1;
  }

  // the server's ring and its answers, on the LCM thread below
  std::mutex ring_mutex;
  groundsim::net::ResendRing ring;
  std::atomic<long long> requests{0}, resent_ok{0}, resent_gone{0}, resent_limited{0}, resent_unknown{0};
  std::atomic<long long> publish_failures{0};
  // per session (by id), the seqs the ring resent: 0/1, grown on demand (under ring_mutex)
  std::map<std::string, std::vector<char>> resent_seqs;
  std::mutex publish_mutex;  // LCM publishes from two threads
  const auto publish = [&](const std::string& channel, const std::vector<std::uint8_t>& b) {
    std::lock_guard<std::mutex> lk(publish_mutex);
    if (lcm.publish(channel, b.data(), static_cast<unsigned>(b.size())) != 0) ++publish_failures;
  };
  struct Responder {
    std::function<void(const groundsim::resend_t&)> f;
  } responder;
  responder.f = [&](const groundsim::resend_t& req) {
    if (!o.ring || req.client_id.empty()) return;
    const bool events = req.stream == groundsim::resend_t::STREAM_EVENTS;
    std::vector<groundsim::net::ResendRing::Message> answer;
    {
      std::lock_guard<std::mutex> lk(ring_mutex);
      answer = ring.answer(req.client_id, events ? "" : req.session_id, req.from_seq, req.to_seq);
      if (!events)
        for (const auto& m : answer) {
          if (m.status != groundsim::net::ResendRing::Status::Ok || m.seq < 0) continue;
          std::vector<char>& v = resent_seqs[req.session_id];
          if (v.size() <= static_cast<std::size_t>(m.seq)) v.resize(static_cast<std::size_t>(m.seq) + 1, 0);
          v[static_cast<std::size_t>(m.seq)] = 1;
        }
    }
    ++requests;
    groundsim::resent_t r{};
    r.request_seq = req.seq;
    r.stream = req.stream;
    r.session_id = req.session_id;
    for (auto& m : answer) {
      using S = groundsim::net::ResendRing::Status;
      r.utime = wallMicros();
      r.seq = m.seq;
      r.last_seq = m.last_seq;
      r.status = static_cast<std::int8_t>(m.status);  // the ring's statuses are resent_t's
      (m.status == S::Ok ? resent_ok : m.status == S::Gone ? resent_gone : m.status == S::Limited ? resent_limited
                                                                                                : resent_unknown)++;
      r.channel = m.channel;
      r.data.assign(m.bytes.begin(), m.bytes.end());
      r.size = static_cast<std::int32_t>(r.data.size());
      publish(groundsim::net::kResentPrefix + req.client_id, encode(r));
    }
  };
  lcm.subscribeFunction(
         groundsim::net::kResendChannel,
         +[](const lcm::ReceiveBuffer* b, const std::string&, Responder* r) {
           groundsim::resend_t m;
           if (m.decode(b->data, 0, static_cast<int>(b->data_size)) < 0) return;
           r->f(m);
         },
         &responder)
      ->setQueueCapacity(groundsim::net::kDeepQueue);
  std::thread lcm_thread([&] {
    while (!g_stop) lcm.handleTimeout(100);
  });

  std::int64_t beat_seq = 0;
  const auto heartbeat = [&] {
    groundsim::server_status_t st{};
    st.utime = wallMicros();
    st.seq = beat_seq++;
    st.server_id = server_id;
    st.workers = 1;
    st.max_sessions = o.sessions;
    for (const Session& s : sessions) {
      if (s.next == 0) continue;
      groundsim::session_info_t in{};
      in.utime = s.state.utime;
      in.seq = s.next - 1;
      in.session_id = s.id;
      in.name = "flood";
      in.mode = 1;
      in.status = s.finished ? groundsim::state_t::STATUS_FINISHED : groundsim::state_t::STATUS_RUNNING;
      in.status_reason = s.finished ? "flood ended" : "";
      in.rate = 1;
      in.publish_rate = o.rate;
      in.tick = s.next - 1;
      in.nvehicles = 1;
      in.vehicle_names = {"sedan"};
      in.wheel_counts = {4};
      in.dt = dt;
      in.server_id = server_id;
      st.sessions.push_back(in);
    }
    st.nsessions = static_cast<std::int32_t>(st.sessions.size());
    publish(groundsim::net::kStatusChannel, encode(st));
  };
  auto next_beat = Clock::now();
  const auto beatIfDue = [&] {
    if (Clock::now() < next_beat) return;
    heartbeat();
    next_beat += std::chrono::seconds(1);
    if (next_beat < Clock::now()) next_beat = Clock::now() + std::chrono::seconds(1);
  };

  // heartbeats, until --go
  while (!g_stop && !o.go.empty() && access(o.go.c_str(), F_OK) != 0) {
    beatIfDue();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }

  // the sessions
  const auto keep = [&](const Session& s, std::int64_t seq, const std::string& channel,
                        const std::vector<std::uint8_t>& b) {
    if (!o.ring) return;
    std::lock_guard<std::mutex> lk(ring_mutex);
    ring.addFrame(s.id, seq, channel, b.data(), b.size());
  };
  const auto start = Clock::now();
  std::int64_t rounds = 0;
  double behind_max = 0;  // rounds behind the schedule, the most seen
  std::vector<std::uint8_t> buf;
  // achieved rate inside and outside bursts
  double burst_wall = 0, burst_msgs = 0;
  while (!g_stop) {
    const double t = std::chrono::duration<double>(Clock::now() - start).count();
    if (t >= o.duration) break;
    beatIfDue();
    const double due = scheduled(o, t);
    if (static_cast<double>(rounds) >= std::floor(due) + 1) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    behind_max = std::max(behind_max, due - static_cast<double>(rounds));
    const bool in_burst = o.burst_every > 0 && t >= o.burst_every && std::fmod(t, o.burst_every) < o.burst_s;
    // one round: a state of every session
    for (std::size_t i = 0; i < sessions.size(); ++i) {
      Session& s = sessions[i];
      fill(s.state, s.next, dt, static_cast<int>(i));
      const int size = s.state.getEncodedSize();
      buf.resize(static_cast<std::size_t>(size));
      s.state.encode(buf.data(), 0, size);
      publish(s.channel, buf);
      keep(s, s.next, s.channel, buf);
      ++s.next;
    }
    if (in_burst) burst_msgs += static_cast<double>(sessions.size());
    ++rounds;
  }
  const double publish_wall = std::chrono::duration<double>(Clock::now() - start).count();
  (void)burst_wall;
  // the last frame of each session: its END entry, then a FINISHED state
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    Session& s = sessions[i];
    groundsim::applied_t a{};
    fill(s.state, s.next, dt, static_cast<int>(i));
    a.utime = s.state.utime;
    a.session_id = s.id;
    a.seq = 0;
    a.frame_seq = s.next;
    a.tick = s.state.tick;
    a.t = s.state.t;
    a.kind = groundsim::applied_t::KIND_END;
    a.vehicle = -1;
    a.reason = "flood ended";
    const auto ab = encode(a);
    const std::string ach = groundsim::net::appliedChannel(s.id);
    publish(ach, ab);
    keep(s, s.next, ach, ab);
    s.state.status = groundsim::state_t::STATUS_FINISHED;
    s.state.status_reason = "flood ended";
    const auto sb = encode(s.state);
    publish(s.channel, sb);
    keep(s, s.next, s.channel, sb);
    ++s.next;
    s.finished = true;
  }
  heartbeat();
  next_beat = Clock::now() + std::chrono::seconds(1);

  long long sent = 0;
  for (const Session& s : sessions) sent += s.next;
  const double sched = scheduled(o, publish_wall);
  std::fprintf(stderr,
               "record_flood: %d sessions, %lld states in %.2f s (%.0f a second; scheduled %.0f per session, "
               "sent %lld per session, %.0f rounds behind at most); bursts: %.0f states; %lld publish failures\n",
               o.sessions, sent, publish_wall, static_cast<double>(sent) / publish_wall, sched,
               static_cast<long long>(sessions[0].next), behind_max, burst_msgs, publish_failures.load());
  // the report: at the sessions' end, and again at exit with the answers
  const auto writeReport = [&](bool final) {
    if (o.report.empty()) return;
    std::ofstream f(o.report + ".tmp");
    f << "{\"publish_s\": " << publish_wall << ", \"rate\": " << o.rate << ", \"burst_every\": " << o.burst_every
      << ", \"burst_s\": " << o.burst_s << ", \"burst_factor\": " << o.burst_factor
      << ", \"scheduled_per_session\": " << std::floor(sched) + 1 << ", \"burst_states\": " << burst_msgs
      << ", \"sent\": " << sent << ", \"publish_failures\": " << publish_failures.load()
      << ", \"ring\": " << (o.ring ? "true" : "false") << ", \"sessions\": {";
    for (std::size_t i = 0; i < sessions.size(); ++i)
      f << (i ? ", " : "") << '"' << sessions[i].id << "\": " << sessions[i].next;
    f << "}";
    if (final) {
      f << ", \"answers\": {\"requests\": " << requests.load() << ", \"resent\": " << resent_ok.load()
        << ", \"gone\": " << resent_gone.load() << ", \"limited\": " << resent_limited.load()
        << ", \"unknown\": " << resent_unknown.load() << "}, \"resent\": {";
      std::lock_guard<std::mutex> lk(ring_mutex);
      bool first = true;
      for (const auto& [id, v] : resent_seqs) {
        f << (first ? "" : ", ") << '"' << id << "\": \"";
        first = false;
        bool comma = false;
        for (std::size_t a = 0; a < v.size();) {
          if (!v[a]) {
            ++a;
            continue;
          }
          std::size_t b = a;
          while (b + 1 < v.size() && v[b + 1]) ++b;
          f << (comma ? "," : "") << a;
          if (b > a) f << '-' << b;
          comma = true;
          a = b + 1;
        }
        f << '"';
      }
      f << "}";
    }
    f << "}\n";
    f.close();
    std::rename((o.report + ".tmp").c_str(), o.report.c_str());
  };
  writeReport(false);
  // heartbeats and answers go on: the recorder asks for the tail and its gaps
  const auto linger_end = Clock::now() + std::chrono::duration<double>(o.linger);
  while (!g_stop && Clock::now() < linger_end) {
    beatIfDue();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  g_stop = true;
  lcm_thread.join();
  writeReport(true);
  std::fprintf(stderr, "record_flood: resend requests %lld; resent %lld, gone %lld, limited %lld, unknown %lld\n",
               requests.load(), resent_ok.load(), resent_gone.load(), resent_limited.load(), resent_unknown.load());
  return 0;
}
