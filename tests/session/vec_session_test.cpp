// Vectorised sessions in process: the service with a recording output and
// the real worker pool, against makeVecEnv stepped directly. Results are
// compared bit for bit; waits are bounded and never part of a verdict.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "experiments/vec_env.hpp"
#include "fakes.hpp"
#include "session/service.hpp"
#include "support/actions.hpp"

namespace groundsim::session::test {
namespace {

using experiments::Layout;

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string& taskScenario() {
  static const std::string text = readFile(std::string(GROUNDSIM_CONFIG_DIR) + "/tasks/fast_car.json");
  return text;
}


class VecService : public ::testing::Test {
 protected:
  static ServiceConfig config() {
    ServiceConfig c;
    c.workers = 2;
    c.max_envs = 64;
    return c;
  }
  VecService() : service_(config(), out_) {}

  VecReply send(VecRequest r) {
    r.request_id = ++next_id_;
    if (r.client_id.empty()) r.client_id = "vec-test";
    service_.handleVecRequest(r);
    VecReply reply;
    EXPECT_TRUE(out_.waitVecReply(r.request_id, &reply)) << "no reply to request " << r.request_id;
    return reply;
  }
  // A request to the session created by create(), with its token.
  VecRequest to(VecOp op) {
    VecRequest r;
    r.op = op;
    r.session_id = id_;
    r.token = token_;
    return r;
  }
  void create(int n, const std::string& text = taskScenario()) {
    VecRequest r;
    r.op = VecOp::Create;
    r.scenario_json = text;
    r.num_envs = n;
    const VecReply reply = send(r);
    ASSERT_TRUE(reply.ok) << reply.error;
    ASSERT_EQ(reply.sessions.size(), 1u);
    ASSERT_TRUE(reply.sessions[0].layout);
    id_ = reply.session_id;
    token_ = reply.token;
    layout_ = *reply.sessions[0].layout;
  }
  VecReply reset(std::int64_t seed) {
    VecRequest r = to(VecOp::Reset);
    r.has_seed = true;
    r.seed = seed;
    return send(r);
  }
  VecReply step(std::vector<float> actions) {
    VecRequest r = to(VecOp::Step);
    r.actions = std::move(actions);
    return send(r);
  }

  RecordingOutput out_;
  SessionService service_;
  std::int64_t next_id_ = 0;
  std::string id_, token_;
  Layout layout_;
};

TEST_F(VecService, StepsAreBitIdenticalToMakeVecEnvInProcess) {
  const int n = 6;
  create(n);
  experiments::VecEnvOptions opt;
  opt.num_threads = 2;  // the session steps on one thread: results must not depend on it
  auto local = experiments::makeVecEnv(taskScenario(), n, opt);
  const Layout& l = local->layout();
  EXPECT_EQ(layout_.observation, l.observation);
  EXPECT_EQ(layout_.action, l.action);
  EXPECT_EQ(layout_.dt, l.dt);
  EXPECT_EQ(layout_.control_period, l.control_period);
  EXPECT_EQ(layout_.wheel_counts, l.wheel_counts);
  EXPECT_EQ(layout_.num_envs, n);

  const std::size_t o = static_cast<std::size_t>(n) * l.obsSize();
  std::vector<float> obs(o);
  std::vector<double> rew(n);
  std::vector<std::uint8_t> term(n), trunc(n);
  local->reset(123, obs.data());
  VecReply r = reset(123);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.obs.size(), o);
  EXPECT_EQ(std::memcmp(r.obs.data(), obs.data(), o * sizeof(float)), 0);
  for (int k = 0; k < 60; ++k) {
    const std::vector<float> a = groundsim::test::sweepActions(l, n, k);
    local->step(a.data(), obs.data(), rew.data(), term.data(), trunc.data());
    r = step(a);
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.env_count, n);
    EXPECT_EQ(r.tick, k + 1);
    ASSERT_EQ(std::memcmp(r.obs.data(), obs.data(), o * sizeof(float)), 0) << "step " << k;
    ASSERT_EQ(std::memcmp(r.rewards.data(), rew.data(), n * sizeof(double)), 0) << "step " << k;
    EXPECT_EQ(r.terminated, term);
    EXPECT_EQ(r.truncated, trunc);
    for (int i = 0; i < n; ++i) {
      const experiments::EnvInfo li = local->info(i);
      EXPECT_EQ(r.infos[i].episode, li.episode);
      EXPECT_EQ(r.infos[i].episode_steps, li.episode_steps);
      EXPECT_EQ(std::memcmp(&r.infos[i].episode_return, &li.episode_return, sizeof(double)), 0);
    }
  }
  // reset of one env to a chosen seed, as in process
  VecRequest one = to(VecOp::ResetEnv);
  one.env = 4;
  one.has_seed = true;
  one.seed = 99;
  r = send(one);
  ASSERT_TRUE(r.ok) << r.error;
  std::vector<float> row(l.obsSize());
  local->resetEnv(4, 99, row.data());
  EXPECT_EQ(r.env_begin, 4);
  EXPECT_EQ(r.env_count, 1);
  EXPECT_EQ(std::memcmp(r.obs.data(), row.data(), row.size() * sizeof(float)), 0);
}

// A snapshot taken from one service, restored into another (another server
// in miniature: its own environments and pool), continues bit for bit.
TEST_F(VecService, SnapshotRestoredIntoAnotherServiceContinuesBitIdentical) {
  const int n = 4, env = 2;
  create(n);
  ASSERT_TRUE(reset(7).ok);
  for (int k = 0; k < 15; ++k) ASSERT_TRUE(step(groundsim::test::sweepActions(layout_, n, k)).ok);
  VecRequest snap = to(VecOp::Snapshot);
  snap.env = env;
  const VecReply s = send(snap);
  ASSERT_TRUE(s.ok) << s.error;
  ASSERT_FALSE(s.snapshot.empty());
  const int a = layout_.actionSize(), o = layout_.obsSize();
  std::vector<std::vector<float>> rows_a, acts;
  for (int k = 0; k < 30; ++k) {
    const std::vector<float> act = groundsim::test::sweepActions(layout_, n, 100 + k);
    acts.emplace_back(act.begin() + env * a, act.begin() + (env + 1) * a);
    const VecReply r = step(act);
    ASSERT_TRUE(r.ok);
    rows_a.emplace_back(r.obs.begin() + env * o, r.obs.begin() + (env + 1) * o);
  }

  RecordingOutput out_b;
  SessionService other(config(), out_b);
  VecRequest c;
  c.op = VecOp::Create;
  c.request_id = 1;
  c.client_id = "b";
  c.scenario_json = taskScenario();
  c.num_envs = 1;
  other.handleVecRequest(c);
  VecReply cr;
  ASSERT_TRUE(out_b.waitVecReply(1, &cr));
  ASSERT_TRUE(cr.ok) << cr.error;
  VecRequest restore;
  restore.op = VecOp::Restore;
  restore.request_id = 2;
  restore.client_id = "b";
  restore.session_id = cr.session_id;
  restore.token = cr.token;
  restore.env = 0;
  restore.snapshot = s.snapshot;
  other.handleVecRequest(restore);
  VecReply rr;
  ASSERT_TRUE(out_b.waitVecReply(2, &rr));
  ASSERT_TRUE(rr.ok) << rr.error;
  for (int k = 0; k < 30; ++k) {
    VecRequest st = restore;
    st.op = VecOp::Step;
    st.request_id = 3 + k;
    st.snapshot.clear();
    st.actions = acts[k];
    other.handleVecRequest(st);
    VecReply r;
    ASSERT_TRUE(out_b.waitVecReply(st.request_id, &r));
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(std::memcmp(r.obs.data(), rows_a[k].data(), o * sizeof(float)), 0) << "step " << k;
  }
}

TEST_F(VecService, BadRequestsAreRefusedNamingTheField) {
  const int n = 3;
  create(n);
  auto refused = [&](VecRequest r, ErrorCode code, const std::string& field) {
    const VecReply reply = send(std::move(r));
    EXPECT_FALSE(reply.ok);
    EXPECT_EQ(reply.code, code) << reply.error;
    EXPECT_EQ(reply.field, field) << reply.error;
    EXPECT_EQ(reply.error.rfind(field + ": ", 0), 0u) << reply.error;
    EXPECT_TRUE(reply.obs.empty());
  };
  VecRequest r = to(VecOp::Step);
  r.actions.assign(n * layout_.actionSize() - 1, 0.0f);
  refused(r, ErrorCode::BadControl, "actions");
  r.actions = groundsim::test::sweepActions(layout_, n, 0);
  r.actions[layout_.actionSize()] = std::nanf("");  // env 1, component 0
  refused(r, ErrorCode::BadControl, "actions[1][0]");
  r.actions[layout_.actionSize()] = std::numeric_limits<float>::infinity();
  refused(r, ErrorCode::BadControl, "actions[1][0]");

  VecRequest unknown = to(VecOp::Step);
  unknown.session_id = "FFFFFFFF";
  refused(unknown, ErrorCode::UnknownSession, "session_id");
  VecRequest no_token = to(VecOp::Reset);
  no_token.token.clear();
  refused(no_token, ErrorCode::Unauthorized, "token");
  VecRequest bad_seed = to(VecOp::Reset);
  bad_seed.has_seed = true;
  bad_seed.seed = -1;
  refused(bad_seed, ErrorCode::BadRequest, "seed");
  VecRequest bad_env = to(VecOp::Snapshot);
  bad_env.env = n;
  refused(bad_env, ErrorCode::BadRequest, "env");
  VecRequest corrupt = to(VecOp::Restore);
  corrupt.snapshot = "not a snapshot";
  refused(corrupt, ErrorCode::BadRequest, "snapshot");
  VecRequest bad_op = to(VecOp::Step);
  bad_op.op = static_cast<VecOp>(77);
  refused(bad_op, ErrorCode::BadRequest, "op");

  // a snapshot of another scenario: the same task on another ground
  VecRequest snap = to(VecOp::Snapshot);
  snap.env = 0;
  VecReply s = send(snap);
  ASSERT_TRUE(s.ok) << s.error;
  ASSERT_GT(s.snapshot.size(), 16u);
  std::string flipped = s.snapshot;
  flipped[flipped.size() / 2] ^= 0x5a;
  VecRequest damaged = to(VecOp::Restore);
  damaged.snapshot = flipped;
  refused(damaged, ErrorCode::BadRequest, "snapshot");

  // creates: too many envs (before anything is built), no task
  VecRequest big;
  big.op = VecOp::Create;
  big.scenario_json = taskScenario();
  big.num_envs = 65;
  refused(big, ErrorCode::BadRequest, "num_envs");
  big.num_envs = 0;
  refused(big, ErrorCode::BadRequest, "num_envs");
  VecRequest no_task;
  no_task.op = VecOp::Create;
  no_task.scenario_json = readFile(std::string(GROUNDSIM_CONFIG_DIR) + "/plain.json");
  no_task.num_envs = 2;
  refused(no_task, ErrorCode::BadScenario, "scenario_json");

  // the session is untouched by all of this
  VecReply ok = reset(1);
  EXPECT_TRUE(ok.ok) << ok.error;
  EXPECT_TRUE(step(groundsim::test::sweepActions(layout_, n, 1)).ok);
}

TEST_F(VecService, ASnapshotOfAnotherScenarioIsRefused) {
  create(2);
  VecRequest snap = to(VecOp::Snapshot);
  snap.env = 1;
  const VecReply s = send(snap);
  ASSERT_TRUE(s.ok) << s.error;
  const std::string first = id_, first_token = token_;
  // the same task with another time limit: another validated document
  std::string other = taskScenario();
  const auto at = other.find("\"time_limit\": 10");
  ASSERT_NE(at, std::string::npos);
  other.replace(at, 16, "\"time_limit\": 11");
  create(2, other);
  VecRequest restore = to(VecOp::Restore);
  restore.snapshot = s.snapshot;
  const VecReply r = send(restore);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.field, "snapshot") << r.error;
}

TEST_F(VecService, ListedWithItsLayoutAndStoppedLikeOtherSessions) {
  create(5);
  const ServiceStatus st = service_.status();
  ASSERT_EQ(st.sessions.size(), 1u);
  const SessionInfo& info = st.sessions[0];
  EXPECT_EQ(info.session_id, id_);
  EXPECT_EQ(info.mode, Mode::Vectorised);
  EXPECT_EQ(info.num_envs, 5);
  EXPECT_EQ(info.dt, layout_.dt);
  EXPECT_EQ(info.control_period, layout_.control_period);
  EXPECT_EQ(info.wheel_counts, layout_.wheel_counts);
  ASSERT_TRUE(info.layout);

  // request_t ops other than stop are refused: it is stepped only by vec requests
  Request lockstep;
  lockstep.op = Op::Step;
  lockstep.request_id = 1000;
  lockstep.client_id = "vec-test";
  lockstep.session_id = id_;
  lockstep.token = token_;
  lockstep.steps = 1;
  service_.handleRequest(lockstep);
  Reply refused;
  ASSERT_TRUE(out_.waitReply(1000, &refused));
  EXPECT_FALSE(refused.ok);
  EXPECT_EQ(refused.code, ErrorCode::WrongMode);

  Request stop = lockstep;
  stop.op = Op::Stop;
  stop.request_id = 1001;
  stop.token.clear();
  service_.handleRequest(stop);
  Reply reply;
  ASSERT_TRUE(out_.waitReply(1001, &reply));
  EXPECT_EQ(reply.code, ErrorCode::Unauthorized);
  stop.token = token_;
  stop.request_id = 1002;
  service_.handleRequest(stop);
  ASSERT_TRUE(out_.waitReply(1002, &reply));
  EXPECT_TRUE(reply.ok) << reply.error;
  const ServiceStatus after = service_.status();
  EXPECT_TRUE(after.sessions.empty());
  ASSERT_EQ(after.ended.size(), 1u);
  EXPECT_EQ(after.ended[0].status, Status::Stopped);
  VecReply gone = step(groundsim::test::sweepActions(layout_, 5, 0));
  EXPECT_FALSE(gone.ok);
  EXPECT_EQ(gone.code, ErrorCode::UnknownSession);
}

}  // namespace
}  // namespace groundsim::session::test
