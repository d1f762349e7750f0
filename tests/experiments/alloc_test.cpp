// VecEnv::step allocates nothing in steady state (no episode ending), on
// one thread and on a pool; resets may (a drawn placement builds a scene).
// Counted at malloc (Eigen allocates with malloc, operator new calls it), by
// interposing malloc, calloc, realloc and the aligned allocators in this
// test binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <string>

#include "task_util.hpp"
#include "support/malloc_counter.hpp"

using groundsim::test::g_allocations;

using namespace groundsim::experiments::test;

namespace {

TEST(Allocation, TheCounterSeesNew) {
  const long before = g_allocations.load();
  auto* p = new std::string(100, 'x');
  EXPECT_GE(g_allocations.load() - before, 1);
  delete p;
}

class StepAllocation : public testing::TestWithParam<int> {};

TEST_P(StepAllocation, ASteadyStepAllocatesNothing) {
  for (const auto& doc : {roadCarDoc(plane(), {{"observation", {"position", "heading", "up_body", "velocity_body",
                                                                "angular_velocity_body", "speed", "wheel_spin",
                                                                "wheel_contact", "wheel_slip", "suspension_travel",
                                                                "height_samples", "goal_body", "goal_distance",
                                                                "previous_action", "time"}},
                                               {"goal", {50, 5}},
                                               {"control_period", 4},
                                               {"reward", {{"progress_to_goal", 1}, {"jerk", 1}, {"tilt", 1}}},
                                               {"randomize", {{"yaw_deg", {-10, 10}}}}},
                                     {{"speed", 5.0}}),
                          reportCarDoc(plane(), {{"observation", {"velocity_body", "wheel_spin", "wheel_contact"}},
                                                 {"action", {{"type", "wheel_torques"}}},
                                                 {"control_period", 8}})}) {
    Batch b(doc, 5, GetParam());
    b.reset(1);
    std::vector<float> action(static_cast<size_t>(b.layout().actionSize()), 0.5f);
    b.setAll(action);
    b.step();  // the first step may fill lazily sized buffers
    const long before = g_allocations.load();
    for (int i = 0; i < 20; ++i) b.step();
    EXPECT_EQ(g_allocations.load() - before, 0) << GetParam() << " threads";
  }
}

INSTANTIATE_TEST_SUITE_P(Threads, StepAllocation, testing::Values(1, 2));

}  // namespace
