// Determinism: the same bits on 1, 2 and 3 threads (autoresets included);
// the same seed gives the same episode, different seeds different initial
// states; one shared model stepped from several threads equals stepping it
// sequentially.
#include <gtest/gtest.h>

#include <cstring>
#include <thread>

#include "experiments/env.hpp"
#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

nlohmann::json randomTask() {
  return {{"observation", {"position", "heading", "velocity_body", "angular_velocity_body", "wheel_spin", "wheel_slip",
                           "previous_action"}},
          {"action", {{"type", "wheel_torques"}, {"max_torque", 1.0}}},
          {"control_period", 8},
          {"time_limit", 0.6},  // 30 actions: several autoresets in a run
          {"reward", {{"progress_along", 1.0}, {"effort", 0.1}}},
          {"randomize", {{"x", {-1.0, 1.0}}, {"yaw_deg", {-30.0, 30.0}}, {"speed", {0.0, 1.0}}}}};
}

struct Trace {
  std::vector<float> obs;
  std::vector<double> rew;
  std::vector<std::uint8_t> flags;
};

// 70 steps of 7 environments with actions from a fixed formula
Trace run(int threads, std::uint64_t seed = 3) {
  Batch b(reportCarDoc(plane(), randomTask()), 7, threads);
  Trace tr;
  b.reset(seed);
  tr.obs = b.obs;
  for (int s = 0; s < 70; ++s) {
    for (int e = 0; e < b.n; ++e)
      for (int k = 0; k < 4; ++k) b.a(e)[k] = static_cast<float>(((s * 7 + e * 3 + k * 5) % 11) / 5.0 - 1.0);
    b.step();
    tr.obs.insert(tr.obs.end(), b.obs.begin(), b.obs.end());
    tr.rew.insert(tr.rew.end(), b.rew.begin(), b.rew.end());
    tr.flags.insert(tr.flags.end(), b.trunc.begin(), b.trunc.end());
    tr.flags.insert(tr.flags.end(), b.term.begin(), b.term.end());
  }
  return tr;
}

bool sameBits(const Trace& a, const Trace& b) {
  return a.obs.size() == b.obs.size() && a.rew.size() == b.rew.size() && a.flags == b.flags &&
         std::memcmp(a.obs.data(), b.obs.data(), a.obs.size() * sizeof(float)) == 0 &&
         std::memcmp(a.rew.data(), b.rew.data(), a.rew.size() * sizeof(double)) == 0;
}

TEST(Determinism, BitIdenticalOnOneTwoAndThreeThreads) {
  const Trace one = run(1), two = run(2), three = run(3);
  EXPECT_TRUE(sameBits(one, two));
  EXPECT_TRUE(sameBits(one, three));
  // the run did end episodes (so autoreset is covered)
  EXPECT_NE(std::find(one.flags.begin(), one.flags.end(), 1), one.flags.end());
}

// The same task without wheel_slip: its cars are stepped four to a SIMD
// group (VecEnv's batched path), which must keep the bits independent of
// the thread count as well.
nlohmann::json batchedTask() {
  nlohmann::json t = randomTask();
  t["observation"] = {"position", "heading", "velocity_body", "angular_velocity_body", "wheel_spin", "previous_action"};
  return t;
}

TEST(Determinism, BatchedTasksAreBitIdenticalOnOneTwoAndThreeThreads) {
  const auto doc = reportCarDoc(plane(), batchedTask());
  ASSERT_TRUE(stepsBatched(*makeTaskContext(scenario::parseScenario(doc), {}, {})));
  ASSERT_FALSE(stepsBatched(*makeTaskContext(scenario::parseScenario(reportCarDoc(plane(), randomTask())), {}, {})))
      << "wheel_slip reads the workspace: not batched";
  auto trace = [&](int threads) {
    Batch b(doc, 7, threads);
    Trace tr;
    b.reset(5);
    for (int s = 0; s < 70; ++s) {
      for (int e = 0; e < b.n; ++e)
        for (int k = 0; k < 4; ++k) b.a(e)[k] = static_cast<float>(((s * 5 + e * 3 + k * 7) % 11) / 5.0 - 1.0);
      b.step();
      tr.obs.insert(tr.obs.end(), b.obs.begin(), b.obs.end());
      tr.rew.insert(tr.rew.end(), b.rew.begin(), b.rew.end());
      tr.flags.insert(tr.flags.end(), b.trunc.begin(), b.trunc.end());
    }
    return tr;
  };
  const Trace one = trace(1), two = trace(2), three = trace(3);
  EXPECT_TRUE(sameBits(one, two));
  EXPECT_TRUE(sameBits(one, three));
  EXPECT_NE(std::find(one.flags.begin(), one.flags.end(), 1), one.flags.end());
}

// With physics.deterministic a car stepped in a SIMD group has exactly the
// arithmetic of the car stepped alone (physics/kernels/batch_step.hpp), so VecEnv's
// batched path must give the bits of each Env stepped by itself through its
// Simulator: the split of a step around the batch (beginStep, finishStep)
// and the autoresets change nothing.
TEST(Determinism, BatchedStepsGiveTheBitsOfEnvsSteppedAloneWhenDeterministic) {
  auto doc = reportCarDoc(plane(), batchedTask());
  doc["physics"] = {{"deterministic", true}};
  auto ctx = makeTaskContext(scenario::parseScenario(doc), {}, {});
  ASSERT_TRUE(stepsBatched(*ctx));
  const int n = 6, steps = 70;
  const size_t m = static_cast<size_t>(ctx->layout.obsSize());
  Batch b(doc, n, 2);
  b.reset(11);
  std::vector<std::unique_ptr<Env>> alone;
  std::vector<float> obs(m * n);
  for (int i = 0; i < n; ++i) {
    alone.push_back(std::make_unique<Env>(ctx, 0));
    alone.back()->reset(11 + static_cast<std::uint64_t>(i), obs.data() + m * i);
  }
  ASSERT_EQ(std::memcmp(obs.data(), b.obs.data(), obs.size() * sizeof(float)), 0);
  int ended = 0;
  for (int s = 0; s < steps; ++s) {
    for (int e = 0; e < n; ++e) {
      for (int k = 0; k < 4; ++k) b.a(e)[k] = static_cast<float>(((s * 3 + e * 5 + k) % 9) / 4.0 - 1.0);
      alone[static_cast<size_t>(e)]->setAction(b.a(e));
    }
    b.step();
    for (int e = 0; e < n; ++e) {
      double r;
      std::uint8_t te, tr;
      alone[static_cast<size_t>(e)]->step(obs.data() + m * e, &r, &te, &tr);
      EXPECT_EQ(r, b.rew[static_cast<size_t>(e)]) << "step " << s << " env " << e;
      EXPECT_EQ(tr, b.trunc[static_cast<size_t>(e)]);
      ended += tr;
    }
    ASSERT_EQ(std::memcmp(obs.data(), b.obs.data(), obs.size() * sizeof(float)), 0) << "step " << s;
  }
  EXPECT_GT(ended, 0) << "the run covers autoresets";
}

TEST(Determinism, SameSeedSameEpisodeDifferentSeedsDifferentStarts) {
  EXPECT_TRUE(sameBits(run(1, 11), run(2, 11)));
  Batch b(reportCarDoc(plane(), randomTask()), 3);
  b.reset(5);
  const std::vector<float> first = b.obs;
  b.reset(5);
  EXPECT_EQ(b.obs, first);
  // environment i is seeded with seed + i: env 1 of seed 5 starts as env 0 of seed 6
  const size_t m = static_cast<size_t>(b.layout().obsSize());
  b.reset(6);
  EXPECT_TRUE(std::equal(b.obs.begin(), b.obs.begin() + m, first.begin() + m));
  // and the three start apart
  EXPECT_FALSE(std::equal(first.begin(), first.begin() + m, first.begin() + m));
  EXPECT_FALSE(std::equal(first.begin() + m, first.begin() + 2 * m, first.begin() + 2 * m));
  // resetting one environment to a seed gives what that seed gives env 0
  b.env->resetEnv(2, 5, b.obs.data() + 2 * m);
  EXPECT_TRUE(std::equal(first.begin(), first.begin() + m, b.obs.begin() + 2 * m));
}

TEST(Determinism, OneSharedModelSteppedFromSeveralThreadsEqualsSequential) {
  // no drawn parameters: every Env steps the context's one Model
  auto ctx = makeTaskContext(scenario::parseScenario(reportCarDoc(plane(), randomTask())), {}, {});
  const int n = 4, steps = 60;
  const size_t m = static_cast<size_t>(ctx->layout.obsSize());
  auto drive = [&](Env& e, int id, std::vector<float>& out) {
    std::vector<float> obs(m);
    double r;
    std::uint8_t te, tr;
    e.reset(100 + id, obs.data());
    for (int s = 0; s < steps; ++s) {
      const float a[4] = {0.5f, 0.5f * id, -0.25f, 1.0f};
      e.setAction(a);
      e.step(obs.data(), &r, &te, &tr);
      out.insert(out.end(), obs.begin(), obs.end());
    }
  };
  std::vector<std::vector<float>> seq(n), par(n);
  for (int i = 0; i < n; ++i) {
    Env e(ctx, 0);
    drive(e, i, seq[static_cast<size_t>(i)]);
  }
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(std::make_unique<Env>(ctx, 0));
  for (int i = 0; i < n; ++i) EXPECT_EQ(&envs[static_cast<size_t>(i)]->simulator().model(), ctx->scene.built.model.get());
  std::vector<std::thread> threads;
  for (int i = 0; i < n; ++i)
    threads.emplace_back([&, i] { drive(*envs[static_cast<size_t>(i)], i, par[static_cast<size_t>(i)]); });
  for (auto& t : threads) t.join();
  for (int i = 0; i < n; ++i) EXPECT_EQ(seq[static_cast<size_t>(i)], par[static_cast<size_t>(i)]) << i;
}

TEST(Determinism, DrawnParametersRebuiltOnWorkerThreadsGiveTheSameBits) {
  // models rebuilt inside the pool's workers at each autoreset
  nlohmann::json t = {{"observation", {"velocity_body", "suspension_travel", "height_samples"}},
                      {"control_period", 5},
                      {"time_limit", 0.1},
                      {"reward", {{"speed_tracking", 1.0}}},
                      {"randomize", {{"speed", {0.0, 5.0}},
                                     {"parameters", {{{"path", "ground.amplitude"}, {"range", {0.01, 0.1}}}}}}}};
  const auto doc = roadCarDoc({{"type", "bumps"}, {"amplitude", 0.05}, {"wavelength_x", 6}, {"wavelength_y", 6}}, t);
  auto trace = [&](int threads) {
    Batch b(doc, 5, threads);
    b.reset(17);
    std::vector<float> out = b.obs;
    b.setAll({0.5f, 0.0f, 0.2f});
    for (int s = 0; s < 16; ++s) {  // three episodes of 5 actions and their resets
      b.step();
      out.insert(out.end(), b.obs.begin(), b.obs.end());
    }
    return out;
  };
  const std::vector<float> one = trace(1);
  EXPECT_EQ(std::memcmp(one.data(), trace(3).data(), one.size() * sizeof(float)), 0);
}

TEST(Determinism, DrawnParametersRebuildTheModelFromTheSeed) {
  nlohmann::json t = randomTask();
  t["observation"] = {"position"};
  t["randomize"] = {{"parameters", {{{"path", "ground.offset"}, {"range", {-0.5, 0.5}}}}}};
  Batch b(reportCarDoc(plane(), t), 2);
  b.reset(9);
  const std::vector<float> first = b.obs;
  // the plane n.p = offset moves: the car stands at a drawn height
  EXPECT_NE(b.o("position.z", 0), b.o("position.z", 1));
  b.reset(9);
  EXPECT_EQ(b.obs, first);
}

}  // namespace
}  // namespace groundsim::experiments::test
