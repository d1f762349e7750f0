// Figures of the network service against a running groundsim-server
// (run.sh starts one in a network namespace and calls this):
//   service_bench roundtrip SCENARIO [--n N]       lockstep step-1 round trip p50/p99
//   service_bench sessions SCENARIO --count N ...  N real time sessions at 50 Hz, 3 subscribers:
//                                                  delivered rate, loss and server load
//   service_bench fairness SCENARIO --greedy N     one 50 Hz real time session beside N fast
//                                                  sessions that want every worker: its states
//   service_bench ratefactor SCENARIO --rate R     simulated seconds per wall second achieved
//   service_bench firststate SCENARIO --count N    N real time creates one after another: create
//                                                  request to the session's first state p50/p99
// Prints one "figure: value" line per result (docs/performance-service.md).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <groundsim/event_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>
#include <groundsim/server_status_t.hpp>
#include <groundsim/state_t.hpp>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using groundsim::request_t;

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Minimal request/reply over one LCM instance (the bench's own, so that its
// timing includes nothing but LCM and the server).
class Caller {
 public:
  explicit Caller(const std::string& url) : lcm_(url) {
    lcm_.subscribe(groundsim::net::kReplyChannel, &Caller::onReply, this);
  }
  groundsim::reply_t call(request_t req) {
    req.request_id = ++id_;
    req.client_id = "bench";
    got_ = false;
    lcm_.publish(groundsim::net::kRequestChannel, &req);
    const auto end = Clock::now() + std::chrono::seconds(60);  // a ceiling for a hung server only
    while (!got_) {
      if (Clock::now() > end) throw std::runtime_error("no reply from groundsim-server in 60 s");
      lcm_.handleTimeout(100);
    }
    return reply_;
  }
  bool good() { return lcm_.good(); }

 private:
  void onReply(const lcm::ReceiveBuffer*, const std::string&, const groundsim::reply_t* r) {
    if (r->client_id == "bench" && r->request_id == id_) reply_ = *r, got_ = true;
  }
  lcm::LCM lcm_;
  std::int64_t id_ = 0;
  bool got_ = false;
  groundsim::reply_t reply_;
};

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5))];
}

groundsim::reply_t create(Caller& c, const std::string& json, int mode) {
  request_t req{};
  req.op = request_t::OP_CREATE;
  req.scenario_json = json;
  req.mode = static_cast<int8_t>(mode);
  req.duration = -1;
  auto r = c.call(req);
  if (!r.ok) throw std::runtime_error("create refused: " + r.error);
  return r;
}

void stop(Caller& c, const groundsim::reply_t& created) {
  request_t req{};
  req.op = request_t::OP_STOP;
  req.session_id = created.session_id;
  req.token = created.token;
  c.call(req);
}

// Cost of one step of this scenario in this process: the part of the round
// trip that is simulation, not service.
double stepMicros(const std::string& json, int steps) {
  auto scene = groundsim::scenario::buildScene(groundsim::scenario::parseScenario(json));
  groundsim::Simulator sim(scene.built.model, scene.built.initial);
  const auto t0 = Clock::now();
  sim.step(steps);
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / steps;
}

int roundtrip(const std::string& url, const std::string& file, int n) {
  const std::string json = readFile(file);
  Caller c(url);
  const auto created = create(c, json, request_t::MODE_LOCKSTEP);
  request_t req{};
  req.op = request_t::OP_STEP;
  req.session_id = created.session_id;
  req.token = created.token;
  req.steps = 1;
  std::vector<double> us;
  us.reserve(n);
  for (int i = 0; i < n + 100; ++i) {
    const auto t0 = Clock::now();
    const auto r = c.call(req);
    const double dt = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
    if (!r.ok || r.nstates != 1) throw std::runtime_error("step failed: " + r.error);
    if (i >= 100) us.push_back(dt);  // warm-up excluded
  }
  stop(c, created);
  const double step = stepMicros(json, 20000);
  std::printf("roundtrip requests: %d\n", n);
  std::printf("roundtrip p50 us: %.1f\n", percentile(us, 0.50));
  std::printf("roundtrip p99 us: %.1f\n", percentile(us, 0.99));
  std::printf("simulation of 1 step us: %.2f\n", step);
  std::printf("roundtrip beyond simulation p50 us: %.1f\n", percentile(us, 0.50) - step);
  std::printf("roundtrip beyond simulation p99 us: %.1f\n", percentile(us, 0.99) - step);
  return 0;
}

// One subscriber: its own LCM instance and thread, deep queue and buffer,
// counting per-session seq gaps.
struct Subscriber {
  explicit Subscriber(const std::string& url) : lcm(groundsim::net::withReceiveBuffer(url)) {
    lcm.subscribe("GROUNDSIM_STATE_.*", &Subscriber::onState, this)->setQueueCapacity(groundsim::net::kDeepQueue);
    thread = std::thread([this] {
      while (!done) lcm.handleTimeout(50);
    });
  }
  void onState(const lcm::ReceiveBuffer*, const std::string&, const groundsim::state_t* m) {
    auto& last = last_seq[m->session_id];
    if (counting) {
      ++received;
      if (last > 0 && m->seq > last + 1) lost += m->seq - last - 1;
    }
    last = m->seq;
  }
  lcm::LCM lcm;
  std::map<std::string, std::int64_t> last_seq;
  std::atomic<bool> counting{false}, done{false};
  std::atomic<long long> received{0}, lost{0};
  std::thread thread;
};

int sessions(const std::string& url, const std::string& file, int count, double seconds, double publish_rate) {
  const std::string json = readFile(file);
  std::vector<std::unique_ptr<Subscriber>> subs;
  for (int i = 0; i < 3; ++i) subs.push_back(std::make_unique<Subscriber>(url));
  // server load from its heartbeat
  lcm::LCM status_lcm(url);
  double load = 0.0;
  int nsessions = 0;
  struct StatusHandler {
    double* load;
    int* n;
    void on(const lcm::ReceiveBuffer*, const std::string&, const groundsim::server_status_t* m) {
      *load = m->load;
      *n = m->nsessions;
    }
  } sh{&load, &nsessions};
  status_lcm.subscribe(groundsim::net::kStatusChannel, &StatusHandler::on, &sh);

  Caller c(url);
  std::vector<groundsim::reply_t> created;
  for (int i = 0; i < count; ++i) {
    request_t req{};
    req.op = request_t::OP_CREATE;
    req.scenario_json = json;
    req.mode = request_t::MODE_REALTIME;
    req.publish_rate = publish_rate;
    req.duration = -1;
    auto r = c.call(req);
    if (!r.ok) throw std::runtime_error("create refused: " + r.error);
    created.push_back(r);
  }
  std::this_thread::sleep_for(std::chrono::seconds(2));  // settle
  for (auto& s : subs) s->counting = true;
  const auto t0 = Clock::now();
  std::vector<double> loads;
  while (Clock::now() - t0 < std::chrono::duration<double>(seconds)) {
    if (status_lcm.handleTimeout(200) > 0) loads.push_back(load);
  }
  for (auto& s : subs) s->counting = false;
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  for (auto& r : created) stop(c, r);
  for (auto& s : subs) {
    s->done = true;
    s->thread.join();
  }
  const double expected = count * publish_rate * elapsed;
  std::printf("sessions: %d real time at %.0f Hz, %.1f s measured, 3 subscribers\n", count, publish_rate, elapsed);
  for (int i = 0; i < 3; ++i)
    std::printf("subscriber %d: received %lld of %.0f expected (%.2f%%), lost %lld\n", i, subs[i]->received.load(),
                expected, 100.0 * subs[i]->received.load() / expected, subs[i]->lost.load());
  std::printf("messages per second per subscriber: %.0f\n", subs[0]->received.load() / elapsed);
  double mean_load = 0;
  for (double l : loads) mean_load += l;
  if (!loads.empty()) mean_load /= loads.size();
  std::printf("server worker load: %.2f (mean of %zu heartbeats)\n", mean_load, loads.size());
  return 0;
}

// Counts one session's states (and its simulated time) on its own thread.
struct Counter {
  Counter(const std::string& url, const std::string& id) : lcm(groundsim::net::withReceiveBuffer(url)) {
    lcm.subscribe(groundsim::net::stateChannel(id), &Counter::onState, this)
        ->setQueueCapacity(groundsim::net::kDeepQueue);
    thread = std::thread([this] {
      while (!done) lcm.handleTimeout(50);
    });
  }
  ~Counter() {
    done = true;
    thread.join();
  }
  void onState(const lcm::ReceiveBuffer*, const std::string&, const groundsim::state_t* m) {
    ++received;
    t = m->t;
  }
  lcm::LCM lcm;
  std::atomic<bool> done{false};
  std::atomic<long long> received{0};
  std::atomic<double> t{0.0};
  std::thread thread;
};

groundsim::reply_t createWith(Caller& c, const std::string& json, int mode, double rate) {
  request_t req{};
  req.op = request_t::OP_CREATE;
  req.scenario_json = json;
  req.mode = static_cast<int8_t>(mode);
  req.rate = rate;
  req.duration = -1;
  auto r = c.call(req);
  if (!r.ok) throw std::runtime_error("create refused: " + r.error);
  return r;
}

int fairness(const std::string& url, const std::string& file, int greedy, double seconds) {
  const std::string json = readFile(file);
  Caller c(url);
  std::vector<groundsim::reply_t> hogs;
  for (int i = 0; i < greedy; ++i) hogs.push_back(createWith(c, json, request_t::MODE_FAST, 0));
  const auto normal = createWith(c, json, request_t::MODE_REALTIME, 1.0);
  Counter counter(url, normal.session_id);
  std::this_thread::sleep_for(std::chrono::seconds(1));  // settle
  const long long n0 = counter.received;
  const auto t0 = Clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  const long long got = counter.received - n0;
  stop(c, normal);
  for (auto& h : hogs) stop(c, h);
  std::printf("fairness: 1 real time session at 50 Hz beside %d fast sessions, %.1f s\n", greedy, elapsed);
  std::printf("states received: %lld of %.0f expected (%.1f%%)\n", got, 50 * elapsed, 100.0 * got / (50 * elapsed));
  return 0;
}

int ratefactor(const std::string& url, const std::string& file, double rate, double seconds) {
  const std::string json = readFile(file);
  Caller c(url);
  const auto s = createWith(c, json, request_t::MODE_REALTIME, rate);
  Counter counter(url, s.session_id);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const double sim0 = counter.t;
  const auto t0 = Clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  const double sim1 = counter.t;
  stop(c, s);
  std::printf("ratefactor asked: %g\n", rate);
  std::printf("ratefactor achieved: %.3f (%.2f simulated s in %.2f wall s)\n", (sim1 - sim0) / elapsed, sim1 - sim0,
              elapsed);
  return 0;
}

}  // namespace

// Create to first state, as a client sees it: each create is timed from its
// request to the first state_t heard on the new session's channel (it may
// come before the reply). In a fleet the create is placed through etcd
// first (docs/fleet.md). The sessions are stopped at the end.
class FirstStates {
 public:
  // a deep receive buffer, as every client that hears states: with sixty
  // sessions publishing, a loaded machine's default buffer overflows and
  // drops the very reply this waits for
  explicit FirstStates(const std::string& url) : lcm_(groundsim::net::withReceiveBuffer(url)) {
    lcm_.subscribe(groundsim::net::kReplyChannel, &FirstStates::onReply, this);
    lcm_.subscribe(std::string(groundsim::net::kStatePrefix) + ".*", &FirstStates::onState, this);
  }
  int run(const std::string& json, int count) {
    std::vector<double> ms;
    std::vector<groundsim::reply_t> created;
    for (int i = 0; i < count; ++i) {
      request_t req{};
      req.op = request_t::OP_CREATE;
      req.scenario_json = json;
      req.mode = request_t::MODE_REALTIME;
      req.rate = 1.0;
      req.duration = -1;
      req.request_id = ++id_;
      req.client_id = "bench-first";
      got_ = false;
      const auto t0 = Clock::now();
      lcm_.publish(groundsim::net::kRequestChannel, &req);
      // a ceiling for a lost or hung create only: the latency is the figure
      // printed, never a verdict (a loaded machine's fleet takes seconds)
      const auto end = t0 + std::chrono::seconds(60);
      while (!got_ || (reply_.ok && !first_.count(reply_.session_id))) {
        if (Clock::now() > end) throw std::runtime_error("create " + std::to_string(i) + ": no reply or no state in 60 s");
        lcm_.handleTimeout(50);
        // a fleet that could not place it (its etcd away) says so: created
        // again half a second later, as a client does, the wait counted in
        // the figure
        if (got_ && !reply_.ok && reply_.error_code == groundsim::event_t::ERR_UNAVAILABLE) {
          std::printf("firststate create %d unavailable (%s): created again\n", i, reply_.error.c_str());
          std::fflush(stdout);
          std::this_thread::sleep_for(std::chrono::milliseconds(500));
          req.request_id = ++id_;
          got_ = false;
          lcm_.publish(groundsim::net::kRequestChannel, &req);
        }
      }
      if (!reply_.ok) throw std::runtime_error("create refused: " + reply_.error);
      ms.push_back(std::chrono::duration<double, std::milli>(first_[reply_.session_id] - t0).count());
      created.push_back(reply_);
    }
    std::printf("firststate creates: %d\n", count);
    std::printf("firststate create to first state p50 ms: %.1f\n", percentile(ms, 0.5));
    std::printf("firststate create to first state p99 ms: %.1f\n", percentile(ms, 0.99));
    std::printf("firststate create to first state max ms: %.1f\n", percentile(ms, 1.0));
    for (const auto& r : created) {
      request_t req{};
      req.op = request_t::OP_STOP;
      req.session_id = r.session_id;
      req.token = r.token;
      req.request_id = ++id_;
      req.client_id = "bench-first";
      lcm_.publish(groundsim::net::kRequestChannel, &req);
    }
    return 0;
  }

 private:
  void onReply(const lcm::ReceiveBuffer*, const std::string&, const groundsim::reply_t* r) {
    if (r->client_id == "bench-first" && r->request_id == id_) reply_ = *r, got_ = true;
  }
  void onState(const lcm::ReceiveBuffer*, const std::string& channel, const groundsim::state_t*) {
    first_.try_emplace(channel.substr(std::strlen(groundsim::net::kStatePrefix)), Clock::now());
  }
  lcm::LCM lcm_;
  std::int64_t id_ = 0;
  bool got_ = false;
  groundsim::reply_t reply_;
  std::map<std::string, Clock::time_point> first_;
};

int main(int argc, char** argv) {
  CLI::App app{"service_bench: figures of groundsim-server"};
  app.require_subcommand(1);
  std::string url = groundsim::net::defaultUrl(), file;
  int n = 10000, count = 200;
  double seconds = 10.0, rate = 50.0;
  app.add_option("--lcm-url", url);
  auto* rt = app.add_subcommand("roundtrip", "lockstep step-1 round trip");
  rt->add_option("SCENARIO", file)->required();
  rt->add_option("--n", n);
  auto* ss = app.add_subcommand("sessions", "real time sessions with 3 subscribers");
  ss->add_option("SCENARIO", file)->required();
  ss->add_option("--count", count);
  ss->add_option("--seconds", seconds);
  ss->add_option("--publish-rate", rate);
  int greedy = 4;
  double factor = 1.0;
  auto* fs = app.add_subcommand("fairness", "one real time session beside greedy fast ones");
  fs->add_option("SCENARIO", file)->required();
  fs->add_option("--greedy", greedy);
  fs->add_option("--seconds", seconds);
  auto* rf = app.add_subcommand("ratefactor", "real-time factor achieved");
  rf->add_option("SCENARIO", file)->required();
  rf->add_option("--rate", factor);
  rf->add_option("--seconds", seconds);
  auto* fst = app.add_subcommand("firststate", "create to first state, real time sessions one after another");
  fst->add_option("SCENARIO", file)->required();
  fst->add_option("--count", count);
  CLI11_PARSE(app, argc, argv);
  try {
    if (*rt) return roundtrip(url, file, n);
    if (*fs) return fairness(url, file, greedy, seconds);
    if (*rf) return ratefactor(url, file, factor, seconds);
    if (*fst) return FirstStates(url).run(readFile(file), count);
    return sessions(url, file, count, seconds, rate);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "service_bench: %s\n", e.what());
    return 1;
  }
}
