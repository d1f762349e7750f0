#include "gate_env.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

namespace groundsim::python {

using experiments::BatchEnv;
using experiments::EnvInfo;
using experiments::ExperimentError;
using experiments::Layout;

struct Gate::Impl {
  std::mutex mutex;
  std::condition_variable cv;
  bool open = false;
  std::atomic<bool> waiting{false};
};

std::shared_ptr<Gate::Impl> Gate::makeImpl() { return std::make_shared<Impl>(); }

void Gate::open() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->open = true;
  }
  impl_->cv.notify_all();
}

bool Gate::waitOpen(double seconds) {
  std::unique_lock lock(impl_->mutex);
  impl_->waiting = true;
  const bool opened = impl_->cv.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return impl_->open; });
  impl_->open = false;
  impl_->waiting = false;
  return opened;
}

bool Gate::waiting() const { return impl_->waiting; }

namespace {

class GateEnv final : public BatchEnv {
 public:
  GateEnv(int num_envs, std::shared_ptr<Gate> gate) : gate_(std::move(gate)) {
    layout_.num_envs = num_envs;
    layout_.dt = 1.0;
    layout_.observation = {"steps"};
    layout_.observation_low = {0.0f};
    layout_.observation_high = {1e9f};
    layout_.action = {"a"};
    layout_.action_low = {-1.0f};
    layout_.action_high = {1.0f};
    layout_.scenario_hash = "gate";
  }
  const Layout& layout() const override { return layout_; }
  void reset(std::optional<std::uint64_t>, float* obs) override {
    steps_ = 0;
    for (int i = 0; i < layout_.num_envs; ++i) obs[i] = 0.0f;
  }
  void resetEnv(int, std::optional<std::uint64_t>, float* obs_row) override { obs_row[0] = 0.0f; }
  void step(const float*, float* obs, double* rewards, std::uint8_t* terminated, std::uint8_t* truncated) override {
    if (!gate_->waitOpen(30.0)) throw ExperimentError("gate", "not opened within 30 s");
    ++steps_;
    for (int i = 0; i < layout_.num_envs; ++i) {
      obs[i] = static_cast<float>(steps_);
      rewards[i] = 0.0;
      terminated[i] = truncated[i] = 0;
    }
  }
  EnvInfo info(int) const override { return EnvInfo{1, steps_, 0.0, false}; }
  std::string snapshot(int) const override { return std::to_string(steps_); }
  void restore(int, const std::string&, float* obs_row) override { obs_row[0] = static_cast<float>(steps_); }
  // draws nothing (Layout::drawn is empty)
  void setRandomization(int, const std::string&) override {}
  void drawn(double*) const override {}
  void render(int, int, int, std::uint8_t*) const override {
    throw ExperimentError("render_mode", "the gate test double has no scene to render");
  }

 private:
  Layout layout_;
  std::shared_ptr<Gate> gate_;
  std::int64_t steps_ = 0;
};

}  // namespace

std::unique_ptr<BatchEnv> makeGateEnv(int num_envs, std::shared_ptr<Gate> gate) {
  return std::make_unique<GateEnv>(num_envs, std::move(gate));
}

}  // namespace groundsim::python
