// A trained driver's policy as a file (docs/drivers.md, "Trained drivers"):
// the observation layout it was trained on, the running statistics that
// normalise it, and a multilayer perceptron evaluated with Eigen. Written
// by examples/export_policy.py from a PPO agent (examples/ppo.py); read
// here without Python by sessions and clients.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "scenario/race_spec.hpp"

namespace groundsim::drivers {

struct PolicyError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Policy {
 public:
  // The file's text (JSON, format "groundsim.policy" version 1). Throws
  // PolicyError naming the field and the reason: a missing or malformed
  // key, sizes that do not chain, a non-finite weight, more than
  // kMaxLayers layers or kMaxUnits units in one.
  static Policy parse(const std::string& text);
  static constexpr int kMaxLayers = 8;
  static constexpr int kMaxUnits = 1024;
  static constexpr std::size_t kMaxFileBytes = scenario::kMaxBotPolicyBytes;
  static constexpr std::size_t kMaxJsonValues = 12u << 20;  // 8 layers of 1024 x 1024 weights and their rows

  // What it observes, as the task wrote it: scenario feature names in
  // order, and the distances of the track features.
  const std::vector<std::string>& features() const { return features_; }
  const std::vector<double>& trackAhead() const { return track_ahead_; }
  int obsSize() const { return static_cast<int>(mean_.size()); }
  int actionSize() const { return static_cast<int>(low_.size()); }
  int controlPeriod() const { return control_period_; }
  double dt() const { return dt_; }
  const std::string& task() const { return task_; }

  // The mean action for one observation (obsSize() values, as the
  // environment returns them: float): normalised by the running
  // statistics, clipped to +-clip, through the layers in float, mapped
  // affinely from [-1, 1] to the action's bounds and clipped to them.
  void act(const float* obs, float* action) const;

 private:
  struct Layer {
    Eigen::MatrixXf w;   // out x in
    Eigen::VectorXf b;
    bool tanh = true;
  };
  std::string task_;
  std::vector<std::string> features_;
  std::vector<double> track_ahead_;
  int control_period_ = 1;
  double dt_ = 0.0;
  Eigen::VectorXd mean_, std_;
  double clip_ = 10.0;
  std::vector<Layer> layers_;
  std::vector<float> low_, high_;
  mutable Eigen::VectorXf x_;               // scratch, sized once: act() allocates nothing
  mutable std::vector<Eigen::VectorXf> out_;  // each layer's output
};

}  // namespace groundsim::drivers
