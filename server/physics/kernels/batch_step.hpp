// Many independent cars of one model stepped together: their states laid
// out as structure of arrays across cars, four cars to a group, one per
// SIMD lane (AVX2 where the CPU has it and the model does not ask for
// determinism; two SSE2 halves otherwise), through the same kernel as the
// single car's specialised step (fast_car_kernel.hpp). Each car gets the
// arithmetic it would get in its own Simulator, so a car stepped in a batch
// matches the same car stepped alone (tests/physics/batch_step_test.cpp).
//
// For the experiments API's in-process environments: one BatchStep per
// model, a vector of States, per-car controls in each State.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"

namespace groundsim {

class BatchStep {
 public:
  // nullptr when the model can be batched: what fast_car.hpp specialises
  // (rigid bodies and springs, circle wheels on a plane, stick-slip
  // friction, semi-implicit Euler); otherwise the reason it cannot.
  static const char* unsupported(const Model& m);

  // Throws std::invalid_argument with the reason when the model cannot be batched.
  explicit BatchStep(std::shared_ptr<const Model> model);
  ~BatchStep();
  BatchStep(const BatchStep&) = delete;
  BatchStep& operator=(const BatchStep&) = delete;

  // Advances every car by n steps of opt.dt, each as Simulator::step does:
  // the commands in cars[i].controls (held for the n steps) become
  // cars[i].applied, the step, then the health check. A car that diverges
  // stops at its last finite state with health and health_reason set, and
  // is skipped from then on; the others go on. States at tick 0 first get
  // their initial energy (as Simulator::restore does). Every State must
  // have the model's size (std::invalid_argument otherwise).
  void step(std::span<State> cars, long long n);
  // The same over states held elsewhere (each environment's Simulator, see
  // Simulator::batchState): car i is *cars[i].
  void step(std::span<State* const> cars, long long n);

  const Model& model() const { return *model_; }
  static constexpr int kLanes = 4;

 private:
  struct Impl;
  std::shared_ptr<const Model> model_;
  std::unique_ptr<Impl> impl_;
  std::vector<State*> ptrs_;  // the contiguous overload's view, reused
};

}  // namespace groundsim
