// physics.deterministic: the same bits on every x86-64 machine. The golden
// hash below was recorded on an AVX2 machine in the generic build; any
// x86-64 CPU (with or without AVX2 and FMA) must reproduce it. The scene
// calls no libm transcendental (flat ground, no steering, per-step
// rotations by the series in math.hpp), so glibc's own FMA dispatch of
// sin/cos/exp cannot enter (docs/performance.md).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "physics/simd/simd_path.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

std::uint64_t fnv1a(const Eigen::VectorXd& y) {
  std::uint64_t h = 1469598103934665603ull;
  const auto* p = reinterpret_cast<const unsigned char*>(y.data());
  for (size_t i = 0; i < sizeof(double) * static_cast<size_t>(y.size()); ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

Eigen::VectorXd run(bool deterministic, std::string* path) {
  Options o;
  o.dt = 5e-5;
  o.deterministic = deterministic;
  CarPlacement at;
  at.wheel_spin = 5.0;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0), {}, at);
  *path = simdPathName(built.model->opt.deterministic);
  Simulator sim(built.model, built.initial);
  sim.controls()[2].drive_torque = sim.controls()[3].drive_torque = 0.3;
  EXPECT_TRUE(sim.step(4000));
  return sim.state().y;
}

TEST(Determinism, TheDeterministicRunHasTheSameBitsOnEveryMachine) {
#if defined(__AVX__) || defined(__FMA__)
  // The promise is for the baseline x86-64 build (docs/performance.md). The
  // clang ASan + fuzz build compiles with -mavx (CMakeLists.txt), so Eigen
  // takes its 4-wide AVX paths there and sums in another order.
  GTEST_SKIP() << "built with AVX (not the baseline x86-64 build the hash is promised for)";
#endif
  std::string path;
  const Eigen::VectorXd y = run(true, &path);
  EXPECT_EQ(path, "generic");
  // the hash of the baseline build's bits; it changes only when the
  // arithmetic does (last: the general loop took the rotation series every
  // path shares, core/pointwise.hpp, a round-off change)
  EXPECT_EQ(fnv1a(y), 0xc96d902022222042ull) << std::hex << fnv1a(y);
}

TEST(Determinism, TheFastPathIsAnotherBuildWhereTheCpuHasIt) {
  std::string fast_path, generic_path;
  const Eigen::VectorXd fast = run(false, &fast_path), generic = run(true, &generic_path);
  if (fast_path == "generic") GTEST_SKIP() << "this CPU has no x86-64-v3: both runs are the generic build";
  // FMA and 4-lane sums round differently: the switch really changes the code
  EXPECT_FALSE((fast.array() == generic.array()).all());
  EXPECT_LT((fast - generic).lpNorm<Eigen::Infinity>(), 1e-9);  // but not the physics
}

}  // namespace
