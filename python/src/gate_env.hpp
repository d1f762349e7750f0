// A BatchEnv for the tests of the binding itself: its step() blocks until
// another thread opens its gate. tests/python/test_gil.py steps it from one
// Python thread and opens the gate from another, which can only happen if
// the binding released the GIL during the step.
#pragma once

#include <memory>

#include "experiments/batch_env.hpp"

namespace groundsim::python {

class Gate {
 public:
  void open();
  // true once open() was called; false after `seconds` without it
  bool waitOpen(double seconds);
  // true while a step waits in waitOpen
  bool waiting() const;

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_ = makeImpl();
  static std::shared_ptr<Impl> makeImpl();
};

// num_envs envs of one observation (the number of steps taken) and one
// action; step() waits for the gate (at most 30 s, then ExperimentError
// with field "gate") and closes it again.
std::unique_ptr<experiments::BatchEnv> makeGateEnv(int num_envs, std::shared_ptr<Gate> gate);

}  // namespace groundsim::python
