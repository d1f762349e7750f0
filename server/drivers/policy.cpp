#include "drivers/policy.hpp"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "scenario/json_limits.hpp"

namespace groundsim::drivers {
namespace {

[[noreturn]] void fail(const std::string& field, const std::string& why) {
  throw PolicyError("policy file: " + field + ": " + why);
}

const nlohmann::json& need(const nlohmann::json& j, const std::string& key, const std::string& where = "") {
  if (!j.is_object() || !j.contains(key)) fail(where + key, "missing");
  return j[key];
}

double number(const nlohmann::json& j, const std::string& field) {
  if (!j.is_number()) fail(field, "expected a number");
  const double x = j.get<double>();
  if (!std::isfinite(x)) fail(field, "not finite");
  return x;
}

std::vector<double> numbers(const nlohmann::json& j, const std::string& field, std::size_t min, std::size_t max) {
  if (!j.is_array()) fail(field, "expected an array of numbers");
  if (j.size() < min || j.size() > max)
    fail(field, std::to_string(j.size()) + " values, expected " + std::to_string(min) + " to " + std::to_string(max));
  std::vector<double> v;
  v.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_number()) fail(field + "/" + std::to_string(i), "expected a number");
    const double x = j[i].get<double>();
    if (!std::isfinite(x)) fail(field + "/" + std::to_string(i), "not finite");
    v.push_back(x);
  }
  return v;
}

}  // namespace

Policy Policy::parse(const std::string& text) {
  // size, depth, value count and duplicate keys, as a scenario's text is
  // checked, before a tree is built (a policy file is 4 levels deep)
  {
    scenario::Budget limits;
    limits.source = "a policy file's limit";
    limits.max_document_bytes = kMaxFileBytes;
    limits.max_depth = 16;
    limits.max_json_values = kMaxJsonValues;
    scenario::IssueList issues;
    scenario::scanText(text, limits, issues);
    try {
      issues.throwIfAny();
    } catch (const scenario::ScenarioError& e) {
      fail("", e.lines("; "));
    }
  }
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) fail("", "not a JSON object");
  if (need(j, "format") != "groundsim.policy") fail("format", "expected \"groundsim.policy\"");
  if (need(j, "version") != 1) fail("version", "this build reads version 1");
  Policy p;
  const nlohmann::json& task = need(j, "task");
  p.task_ = task.is_string() ? task.get<std::string>() : "";
  const nlohmann::json& feats = need(j, "observation");
  if (!feats.is_array() || feats.empty() || feats.size() > 64) fail("observation", "expected 1 to 64 feature names");
  for (const nlohmann::json& f : feats) {
    if (!f.is_string()) fail("observation", "expected feature names (strings)");
    p.features_.push_back(f.get<std::string>());
  }
  p.track_ahead_ = numbers(need(j, "track_ahead"), "track_ahead", 0, 64);
  for (double d : p.track_ahead_)
    if (std::abs(d) > 1e4) fail("track_ahead", "distances within [-1e4, 1e4] m");
  const nlohmann::json& period = need(j, "control_period");
  if (!period.is_number_integer() || period.get<long long>() < 1 || period.get<long long>() > 100000)
    fail("control_period", "expected an integer in [1, 100000]");
  p.control_period_ = period.get<int>();
  p.dt_ = number(need(j, "dt"), "dt");
  if (!(p.dt_ > 0.0 && p.dt_ <= 1.0)) fail("dt", "expected a step in (0, 1] s");

  const nlohmann::json& norm = need(j, "normalise");
  const std::vector<double> mean = numbers(need(norm, "mean", "normalise/"), "normalise/mean", 1, kMaxUnits);
  const std::vector<double> var = numbers(need(norm, "var", "normalise/"), "normalise/var", mean.size(), mean.size());
  p.clip_ = number(need(norm, "clip", "normalise/"), "normalise/clip");
  if (!(p.clip_ > 0.0)) fail("normalise/clip", "expected > 0");
  p.mean_ = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
  p.std_.resize(p.mean_.size());
  for (std::size_t i = 0; i < var.size(); ++i) {
    if (var[i] < 0.0) fail("normalise/var/" + std::to_string(i), "negative");
    p.std_[static_cast<Eigen::Index>(i)] = std::sqrt(var[i] + 1e-8);  // as examples/ppo.py's RunningMeanStd
  }

  const nlohmann::json& layers = need(j, "layers");
  if (!layers.is_array() || layers.empty() || layers.size() > kMaxLayers)
    fail("layers", "expected 1 to " + std::to_string(kMaxLayers) + " layers");
  std::size_t in = mean.size();
  for (std::size_t k = 0; k < layers.size(); ++k) {
    const std::string at = "layers/" + std::to_string(k);
    const nlohmann::json& L = layers[k];
    const nlohmann::json& w = need(L, "weight", at + "/");
    if (!w.is_array() || w.empty() || w.size() > kMaxUnits) fail(at + "/weight", "expected 1 to 1024 rows");
    Layer layer;
    layer.w.resize(static_cast<Eigen::Index>(w.size()), static_cast<Eigen::Index>(in));
    for (std::size_t r = 0; r < w.size(); ++r) {
      const std::vector<double> row = numbers(w[r], at + "/weight/" + std::to_string(r), in, in);
      for (std::size_t c = 0; c < in; ++c)
        layer.w(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = static_cast<float>(row[c]);
    }
    const std::vector<double> b = numbers(need(L, "bias", at + "/"), at + "/bias", w.size(), w.size());
    layer.b = Eigen::Map<const Eigen::VectorXd>(b.data(), static_cast<Eigen::Index>(b.size())).cast<float>();
    const nlohmann::json& act = need(L, "activation", at + "/");
    if (act != "tanh" && act != "none") fail(at + "/activation", "expected \"tanh\" or \"none\"");
    layer.tanh = act == "tanh";
    in = w.size();
    p.layers_.push_back(std::move(layer));
  }
  const std::vector<double> low = numbers(need(j, "action_low"), "action_low", in, in);
  const std::vector<double> high = numbers(need(j, "action_high"), "action_high", in, in);
  for (std::size_t i = 0; i < in; ++i) {
    if (!(low[i] < high[i])) fail("action_high/" + std::to_string(i), "must exceed action_low");
    p.low_.push_back(static_cast<float>(low[i]));
    p.high_.push_back(static_cast<float>(high[i]));
  }
  p.x_.resize(p.mean_.size());
  for (const Layer& L : p.layers_) p.out_.emplace_back(L.b.size());
  return p;
}

void Policy::act(const float* obs, float* action) const {
  for (Eigen::Index i = 0; i < mean_.size(); ++i)
    x_[i] = static_cast<float>(std::clamp((static_cast<double>(obs[i]) - mean_[i]) / std_[i], -clip_, clip_));
  const Eigen::VectorXf* in = &x_;
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    Eigen::VectorXf& y = out_[k];
    y.noalias() = layers_[k].w * *in;
    y += layers_[k].b;
    if (layers_[k].tanh) y = y.array().tanh();
    in = &y;
  }
  const Eigen::VectorXf& a = *in;
  for (std::size_t k = 0; k < low_.size(); ++k) {
    const float mid = 0.5f * (high_[k] + low_[k]), half = 0.5f * (high_[k] - low_[k]);
    action[k] = std::clamp(mid + half * a[static_cast<Eigen::Index>(k)], low_[k], high_[k]);
  }
}

}  // namespace groundsim::drivers
