// step() never allocates: count global allocations around many steps.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "scenes.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace groundsim;
using namespace groundsim::test;

TEST(Allocation, StepAllocatesNothing) {
  Options o;
  o.dt = 5e-5;
  CarPlacement at;
  at.wheel_spin = 5.0;
  auto built = reportCar(o, makeCosineWave(0.5, 2 * kPi), {}, at);
  Simulator sim(built.model, built.initial);
  sim.controls()[1].brake_torque = 0.05;
  sim.controls()[0].steer = 0.2;
  sim.step(10);
  const long before = g_allocations.load();
  ASSERT_TRUE(sim.step(5000));  // includes energy checks every 256 steps
  EXPECT_EQ(g_allocations.load(), before);
}
