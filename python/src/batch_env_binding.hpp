// The Python face of any experiments::BatchEnv (in process or remote): a
// handle that owns the environment, checks the caller's numpy buffers and
// steps with the GIL released. Factories (module.cpp, and the remote one)
// build a BatchEnv and hand it to wrapBatchEnv; everything else is generic.
#pragma once

#include <memory>
#include <mutex>

#include <pybind11/pybind11.h>

#include "experiments/batch_env.hpp"

namespace groundsim::python {

// One BatchEnv behind a mutex: two Python threads stepping the same handle
// take turns instead of racing inside the C++ environment (the GIL is not
// held while it runs). close() drops the environment; later calls fail.
class EnvHandle {
 public:
  explicit EnvHandle(std::unique_ptr<experiments::BatchEnv> env);
  ~EnvHandle();
  const experiments::Layout& layout() const { return layout_; }
  // The environment, with the lock held by the caller; throws once closed.
  experiments::BatchEnv& env();
  std::mutex& mutex() { return mutex_; }
  void close();
  bool closed() const { return env_ == nullptr; }

 private:
  std::unique_ptr<experiments::BatchEnv> env_;
  experiments::Layout layout_;  // kept: readable after close()
  std::mutex mutex_;
};

// Registers Layout, EnvInfo and the handle class ("BatchEnv") on the module.
void bindBatchEnv(pybind11::module_& m);
// Translates ExperimentError and scenario::ScenarioError into
// groundsim.ExperimentError / groundsim.ScenarioError (groundsim/_errors.py).
void registerErrorTranslators();

}  // namespace groundsim::python
