// Vectorised sessions end to end: the real groundsim-server over UDP
// multicast in a private network namespace, driven by RemoteVecEnv, against
// makeVecEnv in this process. Verdicts are exact (bit-identical results,
// named fields); waits are generous timeouts only.
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <groundsim/event_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>
#include <groundsim/state_t.hpp>
#include <groundsim/vec_reply_t.hpp>
#include <groundsim/vec_request_t.hpp>

#include "client/experiments/remote_vec_env.hpp"
#include "experiments/vec_env.hpp"
#include "process.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/limits.hpp"
#include "test_env.hpp"
#include "support/actions.hpp"

namespace groundsim::itest {
namespace {

using experiments::ExperimentError;
using experiments::Layout;
using experiments::RemoteError;
using experiments::RemoteVecEnv;
using experiments::RemoteVecOptions;

// a second server of its own, on another port (same loopback-only group)
const std::string kUrl2 = "udpm://239.255.76.67:7668?ttl=0";

std::string taskScenario() {
  std::ifstream in(std::string(GROUNDSIM_CONFIG_DIR) + "/tasks/fast_car.json");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}


RemoteVecOptions at(const std::string& url) {
  RemoteVecOptions o;
  o.lcm_url = url;
  return o;
}

class Vec : public ::testing::Test {
 protected:
  void SetUp() override { server_ = start(kUrl); }
  void TearDown() override {
    for (auto* s : {&server_, &server2_})
      if (*s) {
        (*s)->signal(SIGTERM);
        (*s)->wait(30);
        s->reset();
      }
  }
  static std::unique_ptr<Process> start(const std::string& url) {
    auto p = std::make_unique<Process>(std::vector<std::string>{kServer, "--lcm-url", url, "--workers", "2",
                                                                "--max-envs", "1024", "--quiet"});
    EXPECT_TRUE(p->waitForOutput("groundsim-server ready", 20)) << p->wait(1).err;
    return p;
  }

  // Steps `remote` and a makeVecEnv of the same scenario with the same seed
  // and actions; every observation, reward and flag must be the same bits.
  // fresh: remote was not reset before (its episode counters start as the local ones).
  void expectSameAsInProcess(RemoteVecEnv& remote, int n, int steps, bool fresh = true) {
    experiments::VecEnvOptions opt;
    opt.num_threads = 2;
    auto local = experiments::makeVecEnv(taskScenario(), n, opt);
    const Layout& l = local->layout();
    ASSERT_EQ(remote.layout().observation, l.observation);
    ASSERT_EQ(remote.layout().action, l.action);
    EXPECT_EQ(remote.layout().dt, l.dt);
    EXPECT_EQ(remote.layout().control_period, l.control_period);
    EXPECT_EQ(remote.layout().wheel_counts, l.wheel_counts);
    const std::size_t o = static_cast<std::size_t>(n) * l.obsSize();
    std::vector<float> obs_l(o), obs_r(o);
    std::vector<double> rew_l(n), rew_r(n);
    std::vector<std::uint8_t> te_l(n), te_r(n), tr_l(n), tr_r(n);
    local->reset(2024, obs_l.data());
    remote.reset(2024, obs_r.data());
    ASSERT_EQ(std::memcmp(obs_l.data(), obs_r.data(), o * sizeof(float)), 0);
    for (int k = 0; k < steps; ++k) {
      const std::vector<float> a = groundsim::test::sweepActions(l, n, k);
      local->step(a.data(), obs_l.data(), rew_l.data(), te_l.data(), tr_l.data());
      remote.step(a.data(), obs_r.data(), rew_r.data(), te_r.data(), tr_r.data());
      ASSERT_EQ(std::memcmp(obs_l.data(), obs_r.data(), o * sizeof(float)), 0) << "step " << k;
      ASSERT_EQ(std::memcmp(rew_l.data(), rew_r.data(), n * sizeof(double)), 0) << "step " << k;
      ASSERT_EQ(te_l, te_r) << "step " << k;
      ASSERT_EQ(tr_l, tr_r) << "step " << k;
    }
    for (int i = 0; i < n; ++i) {
      if (fresh) EXPECT_EQ(remote.info(i).episode, local->info(i).episode);
      EXPECT_EQ(remote.info(i).episode_steps, local->info(i).episode_steps);
    }
  }

  std::unique_ptr<Process> server_, server2_;
};

TEST_F(Vec, RemoteIsBitIdenticalToInProcess) {
  RemoteVecEnv remote(taskScenario(), 16, at(kUrl));
  expectSameAsInProcess(remote, 16, 80);
  remote.close();
}

// 1,024 environments: a reply of several parts, each one datagram below
// the documented limit, put back together exactly.
TEST_F(Vec, ThousandEnvironmentsAreSplitAndReassembled) {
  struct Parts {
    int max_nparts = 0;
    std::size_t largest = 0;
    void on(const lcm::ReceiveBuffer* b, const std::string&) {
      groundsim::vec_reply_t m;
      if (!net::decodeMessage(b->data, static_cast<int>(b->data_size), m, "vec_reply_t").ok()) return;
      max_nparts = std::max(max_nparts, m.nparts);
      largest = std::max<std::size_t>(largest, b->data_size);
    }
  } parts;
  lcm::LCM ear(net::withReceiveBuffer(kUrl));
  ear.subscribe(net::kVecReplyChannel, &Parts::on, &parts)->setQueueCapacity(net::kDeepQueue);
  std::atomic<bool> done{false};
  std::thread listen([&] {
    while (!done) ear.handleTimeout(50);
  });
  {
    RemoteVecEnv remote(taskScenario(), 1024, at(kUrl));
    expectSameAsInProcess(remote, 1024, 5);
  }
  done = true;
  listen.join();
  EXPECT_GT(parts.max_nparts, 1);
  EXPECT_LE(parts.largest, net::kMaxVecPartBytes);
}

TEST_F(Vec, SnapshotFromOneServerProcessContinuesBitIdenticalInAnother) {
  server2_ = start(kUrl2);
  const int n = 4, env = 1;
  RemoteVecEnv a(taskScenario(), n, at(kUrl));
  const Layout& l = a.layout();
  const int o = l.obsSize(), k = l.actionSize();
  std::vector<float> obs(static_cast<std::size_t>(n) * o);
  std::vector<double> rew(n);
  std::vector<std::uint8_t> te(n), tr(n);
  a.reset(5, obs.data());
  for (int s = 0; s < 12; ++s) a.step(groundsim::test::sweepActions(l, n, s).data(), obs.data(), rew.data(), te.data(), tr.data());
  const std::string snap = a.snapshot(env);
  std::vector<std::vector<float>> rows, acts;
  std::vector<double> rewards;
  for (int s = 0; s < 40; ++s) {
    const std::vector<float> act = groundsim::test::sweepActions(l, n, 50 + s);
    a.step(act.data(), obs.data(), rew.data(), te.data(), tr.data());
    acts.emplace_back(act.begin() + env * k, act.begin() + (env + 1) * k);
    rows.emplace_back(obs.begin() + env * o, obs.begin() + (env + 1) * o);
    rewards.push_back(rew[env]);
  }
  a.close();

  RemoteVecEnv b(taskScenario(), 1, at(kUrl2));
  std::vector<float> row(o);
  double r1 = 0;
  std::uint8_t t1 = 0, u1 = 0;
  b.restore(0, snap, row.data());
  for (int s = 0; s < 40; ++s) {
    b.step(acts[s].data(), row.data(), &r1, &t1, &u1);
    ASSERT_EQ(std::memcmp(row.data(), rows[s].data(), o * sizeof(float)), 0) << "step " << s;
    ASSERT_EQ(std::memcmp(&r1, &rewards[s], sizeof r1), 0) << "step " << s;
  }
}

// Raw requests a RemoteVecEnv would never send, and bad values it passes on.
TEST_F(Vec, BadRequestsAreAnsweredNamingTheFieldAndTheServerKeepsServing) {
  RemoteVecEnv remote(taskScenario(), 3, at(kUrl));
  const Layout& l = remote.layout();
  std::vector<float> obs(3 * l.obsSize());
  std::vector<double> rew(3);
  std::vector<std::uint8_t> te(3), tr(3);
  remote.reset(1, obs.data());
  auto field = [&](auto&& call) -> std::string {
    try {
      call();
    } catch (const ExperimentError& e) {
      return e.field();
    }
    return "(no error)";
  };
  std::vector<float> nan = groundsim::test::sweepActions(l, 3, 0);
  nan[2 * l.actionSize() + l.actionSize() - 1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(field([&] { remote.step(nan.data(), obs.data(), rew.data(), te.data(), tr.data()); }),
            "actions[2][" + std::to_string(l.actionSize() - 1) + "]");
  EXPECT_EQ(field([&] { remote.restore(0, "garbage snapshot", obs.data()); }), "snapshot");
  EXPECT_EQ(field([&] { remote.reset(std::numeric_limits<std::uint64_t>::max(), obs.data()); }), "seed");
  EXPECT_EQ(field([&] { RemoteVecEnv big(taskScenario(), 5000, at(kUrl)); }), "num_envs");

  // the raw wire: wrong action count, unknown session, missing token, garbage
  struct Ear {
    std::vector<groundsim::vec_reply_t> replies;
    void on(const lcm::ReceiveBuffer* b, const std::string&) {
      groundsim::vec_reply_t m;
      if (net::decodeMessage(b->data, static_cast<int>(b->data_size), m, "vec_reply_t").ok() &&
          m.client_id == "raw")
        replies.push_back(m);
    }
  } ear;
  lcm::LCM lcm(kUrl);
  lcm.subscribe(net::kVecReplyChannel, &Ear::on, &ear);
  auto ask = [&](groundsim::vec_request_t r) -> groundsim::vec_reply_t {
    static std::int64_t id = 0;
    r.request_id = ++id;
    r.client_id = "raw";
    r.nactions = static_cast<int32_t>(r.actions.size());
    r.snapshot_size = static_cast<int32_t>(r.snapshot.size());
    lcm.publish(net::kVecRequestChannel, &r);
    for (int i = 0; i < 100; ++i) {
      lcm.handleTimeout(100);
      for (const auto& m : ear.replies)
        if (m.request_id == r.request_id) return m;
    }
    ADD_FAILURE() << "no reply to raw request " << r.request_id;
    return {};
  };
  groundsim::vec_request_t step{};
  step.op = groundsim::vec_request_t::OP_STEP;
  step.session_id = remote.sessionId();
  step.token = "";
  step.actions.assign(3 * l.actionSize(), 0.0f);
  groundsim::vec_reply_t r = ask(step);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.field, "token") << r.error;
  step.session_id = "ABCDEF01";
  r = ask(step);
  EXPECT_EQ(r.field, "session_id") << r.error;
  EXPECT_EQ(r.error_code, groundsim::event_t::ERR_UNKNOWN_SESSION);
  const std::string junk(300, '\x11');
  lcm.publish(net::kVecRequestChannel, junk.data(), static_cast<unsigned>(junk.size()));

  // still serving, with the same session and the same results as in process
  expectSameAsInProcess(remote, 3, 10, /*fresh=*/false);
}

TEST_F(Vec, ARealtimeSessionBesideAVectorisedOneKeepsPublishing) {
  // a real-time session of the plain scenario, watched
  struct Watch {
    std::string id;
    std::int64_t reply_id = 0;
    groundsim::reply_t reply;
    bool got = false;
    std::atomic<std::int64_t> states{0};  // counted on the listening thread, read on this one
    void onReply(const lcm::ReceiveBuffer* b, const std::string&) {
      groundsim::reply_t m;
      if (net::decodeMessage(b->data, static_cast<int>(b->data_size), m, "reply_t").ok() &&
          m.client_id == "watch" && m.request_id == reply_id)
        reply = m, got = true;
    }
    void onState(const lcm::ReceiveBuffer*, const std::string&) { ++states; }
  } w;
  lcm::LCM lcm(net::withReceiveBuffer(kUrl));
  lcm.subscribe(net::kReplyChannel, &Watch::onReply, &w);
  std::ifstream in(kPlain);
  std::stringstream text;
  text << in.rdbuf();
  groundsim::request_t create{};
  create.op = groundsim::request_t::OP_CREATE;
  create.request_id = w.reply_id = 1;
  create.client_id = "watch";
  create.scenario_json = text.str();
  create.mode = groundsim::request_t::MODE_REALTIME;
  create.duration = -1;
  lcm.publish(net::kRequestChannel, &create);
  for (int i = 0; i < 100 && !w.got; ++i) lcm.handleTimeout(100);
  ASSERT_TRUE(w.got && w.reply.ok) << w.reply.error;
  lcm.subscribe(net::stateChannel(w.reply.session_id), &Watch::onState, &w)->setQueueCapacity(net::kDeepQueue);
  std::atomic<bool> done{false};
  std::thread listen([&] {
    while (!done) lcm.handleTimeout(50);
  });

  // the vectorised session keeps a worker busy with back-to-back batched steps
  RemoteVecEnv remote(taskScenario(), 256, at(kUrl));
  const Layout& l = remote.layout();
  const int n = 256;
  std::vector<float> obs(static_cast<std::size_t>(n) * l.obsSize());
  std::vector<double> rew(n);
  std::vector<std::uint8_t> te(n), tr(n);
  remote.reset(0, obs.data());
  // batched steps back to back until the real-time session has published
  // 30 states meanwhile (0.6 s of its 50 Hz): a starved session publishes
  // none. The wall-clock ceiling only ends a hung test; how long it took is
  // printed (a loaded machine publishes more slowly, and still passes).
  const std::int64_t before = w.states;
  const auto start = std::chrono::steady_clock::now();
  int steps = 0;
  while (w.states - before < 30 && std::chrono::steady_clock::now() - start < std::chrono::seconds(120)) {
    remote.step(groundsim::test::sweepActions(l, n, steps).data(), obs.data(), rew.data(), te.data(), tr.data());
    ++steps;
  }
  const std::int64_t during = w.states - before;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  done = true;
  listen.join();
  std::printf("beside %d batched steps: %lld states published in %.2f s\n", steps, static_cast<long long>(during), wall);
  EXPECT_GT(steps, 0);
  EXPECT_GE(during, 30) << steps << " batched steps in " << wall << " s";
}

// A client busy elsewhere for longer than the heartbeat timeout (e.g. a
// learner's update) finds the heartbeats that queued meanwhile.
TEST_F(Vec, AnIdleClientDoesNotTakeALivingServerForAGoneOne) {
  RemoteVecEnv remote(taskScenario(), 2, at(kUrl));
  std::vector<float> obs(2 * remote.layout().obsSize());
  remote.reset(0, obs.data());
  std::this_thread::sleep_for(std::chrono::duration<double>(net::kHeartbeatTimeout + 1.5));
  EXPECT_NO_THROW(remote.reset(0, obs.data()));
}

TEST_F(Vec, TheClientSaysWhenTheServerIsGone) {
  RemoteVecEnv remote(taskScenario(), 2, at(kUrl));
  std::vector<float> obs(2 * remote.layout().obsSize());
  remote.reset(0, obs.data());
  server_->signal(SIGKILL);
  server_->wait(30);
  server_.reset();
  try {
    remote.reset(0, obs.data());
    FAIL() << "a reset without a server returned";
  } catch (const RemoteError& e) {
    EXPECT_NE(std::string(e.what()).find("no heartbeat from groundsim-server"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace groundsim::itest
