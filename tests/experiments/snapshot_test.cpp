// Snapshots: restore then step equals the original bit for bit (also into
// another VecEnv of the same scenario, also with drawn parameters), and
// every way a snapshot can be wrong is refused with its reason.
#include <gtest/gtest.h>

#include <cstring>

#include "experiments/snapshot.hpp"
#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

nlohmann::json carTask() {
  return {{"observation", {"position", "velocity_body", "wheel_spin", "wheel_contact", "wheel_slip",
                           "suspension_travel", "previous_action", "time"}},
          {"control_period", 4},
          {"time_limit", 0.4},
          {"reward", {{"progress_along", 1.0}, {"jerk", 0.1}}},
          {"randomize", {{"yaw_deg", {-20.0, 20.0}}, {"speed", {2.0, 6.0}}}}};
}

std::vector<float> steps(Batch& b, int n) {
  std::vector<float> out;
  for (int s = 0; s < n; ++s) {
    for (int e = 0; e < b.n; ++e) {
      b.a(e)[0] = 0.3f + 0.05f * static_cast<float>(s % 5);
      b.a(e)[2] = 0.1f * static_cast<float>((s + e) % 7 - 3);
    }
    b.step();
    out.insert(out.end(), b.obs.begin(), b.obs.end());
    for (double r : b.rew) {
      float f[2];
      std::memcpy(f, &r, sizeof r);
      out.insert(out.end(), f, f + 2);
    }
    out.insert(out.end(), b.term.begin(), b.term.end());
    out.insert(out.end(), b.trunc.begin(), b.trunc.end());
  }
  return out;
}

void roundTrip(const nlohmann::json& doc) {
  Batch a(doc, 2), b(doc, 2);
  a.reset(7);
  steps(a, 13);  // mid-episode (and past an autoreset: 10 actions per episode)
  const std::string s0 = a.env->snapshot(0), s1 = a.env->snapshot(1);
  const std::vector<float> at_snapshot = a.obs;
  const EnvInfo info0 = a.env->info(0);
  const std::vector<float> original = steps(a, 25);
  b.reset(99);  // elsewhere entirely
  const size_t m = static_cast<size_t>(b.layout().obsSize());
  b.env->restore(0, s0, b.obs.data());
  b.env->restore(1, s1, b.obs.data() + m);
  EXPECT_EQ(b.obs, at_snapshot);  // restore returns the observation of the snapshot
  EXPECT_EQ(b.env->info(0).episode, info0.episode);
  EXPECT_EQ(b.env->info(0).episode_steps, info0.episode_steps);
  EXPECT_EQ(b.env->info(0).episode_return, info0.episode_return);
  const std::vector<float> restored = steps(b, 25);
  ASSERT_EQ(restored.size(), original.size());
  EXPECT_EQ(std::memcmp(restored.data(), original.data(), original.size() * sizeof(float)), 0);
  // and a snapshot of the restored environment is the same bytes
  Batch c(doc, 2);
  c.env->restore(1, s0, c.obs.data() + m);
  EXPECT_EQ(c.env->snapshot(1), s0);
}

TEST(Snapshots, RestoreThenStepEqualsTheOriginalBitForBit) {
  roundTrip(roadCarDoc(plane(), carTask()));
}

TEST(Snapshots, RoundTripWithDrawnParametersRebuildsTheirModel) {
  nlohmann::json t = carTask();
  t["randomize"]["parameters"] = {{{"path", "ground.amplitude"}, {"range", {0.02, 0.1}}},
                                  {{"path", "vehicle.mass"}, {"range", {1200.0, 1800.0}}}};
  roundTrip(roadCarDoc({{"type", "bumps"}, {"amplitude", 0.05}, {"wavelength_x", 6}, {"wavelength_y", 6}}, t));
}

class SnapshotErrors : public ::testing::Test {
 protected:
  SnapshotErrors() : b(roadCarDoc(plane(), carTask()), 1) {
    b.reset(1);
    steps(b, 3);
    good = b.env->snapshot(0);
  }
  // the reason restore gives; the environment must be left as it was
  std::string refusal(const std::string& bytes) {
    const std::string before = b.env->snapshot(0);
    try {
      b.env->restore(0, bytes, b.obs.data());
    } catch (const ExperimentError& e) {
      EXPECT_EQ(e.field(), "snapshot");
      EXPECT_EQ(b.env->snapshot(0), before) << "a refused restore changed the environment";
      return e.what();
    }
    ADD_FAILURE() << "snapshot accepted";
    return "";
  }
  // re-seals an edited snapshot with a valid checksum
  static std::string sealed(std::string s) {
    s.resize(s.size() - 8);
    std::uint64_t h = fnv1a64(s.data(), s.size());
    for (int i = 0; i < 8; ++i) s.push_back(static_cast<char>(h >> (8 * i)));
    return s;
  }
  Batch b;
  std::string good;
};

TEST_F(SnapshotErrors, GoodOneIsAccepted) { EXPECT_NO_THROW(b.env->restore(0, good, b.obs.data())); }

TEST_F(SnapshotErrors, AnotherScenario) {
  nlohmann::json t = carTask();
  t["control_period"] = 5;  // only the task differs: still another scenario
  Batch other(roadCarDoc(plane(), t), 1);
  other.reset(1);
  EXPECT_NE(refusal(other.env->snapshot(0)).find("another scenario"), std::string::npos);
}

TEST_F(SnapshotErrors, TruncatedEmptyAndNotASnapshot) {
  EXPECT_NE(refusal("").find("truncated"), std::string::npos);
  EXPECT_NE(refusal(good.substr(0, good.size() / 2)).find("checksum"), std::string::npos);
  EXPECT_NE(refusal(sealed(good.substr(0, good.size() - 40))).find("truncated"), std::string::npos);
  EXPECT_NE(refusal(std::string(100, 'x')).find("bad magic"), std::string::npos);
}

TEST_F(SnapshotErrors, BadChecksum) {
  std::string s = good;
  s[s.size() / 2] ^= 0x10;
  EXPECT_NE(refusal(s).find("checksum mismatch"), std::string::npos);
}

TEST_F(SnapshotErrors, WrongVersion) {
  // version 1 (before curricula: no ranges) and a future one
  for (const char v : {char{1}, static_cast<char>(kSnapshotVersion + 1)}) {
    std::string s = good;
    s[8] = v;
    EXPECT_NE(refusal(sealed(s)).find("version " + std::to_string(static_cast<int>(v))), std::string::npos);
  }
}

TEST_F(SnapshotErrors, SizesThatDoNotFitTheScenario) {
  EnvSnapshot p = decodeSnapshot(good, b.layout().scenario_hash);
  EnvSnapshot y = p;
  y.state.y.conservativeResize(y.state.y.size() - 1);
  EXPECT_NE(refusal(encodeSnapshot(b.layout().scenario_hash, y)).find("state of"), std::string::npos);
  EnvSnapshot a = p;
  a.previous_action.push_back(0.0f);
  EXPECT_NE(refusal(encodeSnapshot(b.layout().scenario_hash, a)).find("previous action"), std::string::npos);
  EnvSnapshot d = p;
  d.drawn.push_back(1.0);
  EXPECT_NE(refusal(encodeSnapshot(b.layout().scenario_hash, d)).find("drawn values"), std::string::npos);
  EnvSnapshot o = p;
  o.observation.pop_back();
  EXPECT_NE(refusal(encodeSnapshot(b.layout().scenario_hash, o)).find("observation"), std::string::npos);
  EnvSnapshot w = p;
  w.state.controls.push_back({});
  EXPECT_NE(refusal(encodeSnapshot(b.layout().scenario_hash, w)).find("wheel controls"), std::string::npos);
  EnvSnapshot c = p;
  c.state.car_controls.push_back({});
  EXPECT_NE(refusal(encodeSnapshot(b.layout().scenario_hash, c)).find("road cars"), std::string::npos);
  EnvSnapshot n = p;
  n.state.y[3] = std::nan("");
  EXPECT_NE(refusal(encodeSnapshot(b.layout().scenario_hash, n)).find("non-finite"), std::string::npos);
}

TEST_F(SnapshotErrors, ACountLargerThanTheBytesIsRefusedBeforeAllocating) {
  // the state vector's count sits after magic, version and the hash
  std::string s = good;
  const size_t at = 8 + 4 + 4 + b.layout().scenario_hash.size();
  for (int i = 0; i < 4; ++i) s[at + i] = static_cast<char>(0xff);
  EXPECT_NE(refusal(sealed(s)).find("more than the"), std::string::npos);
}

}  // namespace
}  // namespace groundsim::experiments::test
