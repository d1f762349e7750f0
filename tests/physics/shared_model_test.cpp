// One immutable model, many simulations on several threads: what the
// experiments API will do. An expression ground is the model part that used
// to hold evaluation state (a parser and its variables).
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "scenario/expression_ground.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

constexpr int kRuns = 6;
constexpr int kSteps = 3000;

std::shared_ptr<const Model> bumpyModel(State* initial) {
  Options o;
  o.dt = 2e-4;
  CarParams p;
  p.rim_points = 12;
  CarPlacement at;
  at.wheel_spin = 3.0;
  auto built = reportCar(o, std::make_shared<scenario::ExpressionGround>("z - 0.3*cos(x)*cos(0.7*y)"), p, at);
  *initial = built.initial;
  return built.model;
}

// Run k: its own drive torque, so a shared parser would mix different points.
Eigen::VectorXd run(const std::shared_ptr<const Model>& m, const State& initial, int k) {
  Simulator sim(m, initial);
  for (auto& c : sim.controls()) c.drive_torque = 0.2 * k;
  sim.controls()[0].steer = 0.1 * k;
  EXPECT_TRUE(sim.step(kSteps)) << k;
  return sim.state().y;
}

TEST(SharedModel, ManySimulationsOnThreadsMatchThemOneAfterAnother) {
  State initial;
  const auto model = bumpyModel(&initial);
  std::vector<Eigen::VectorXd> serial(kRuns), parallel(kRuns);
  for (int k = 0; k < kRuns; ++k) serial[k] = run(model, initial, k);
  std::vector<std::thread> threads;
  for (int k = 0; k < kRuns; ++k) threads.emplace_back([&, k] { parallel[k] = run(model, initial, k); });
  for (auto& t : threads) t.join();
  for (int k = 0; k < kRuns; ++k) {
    ASSERT_EQ(parallel[k].size(), serial[k].size());
    EXPECT_TRUE((parallel[k].array() == serial[k].array()).all()) << "run " << k << " differs";
  }
  // the runs are really different from one another
  EXPECT_FALSE((serial[1].array() == serial[2].array()).all());
}

}  // namespace
