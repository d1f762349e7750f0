// VecEnv: N environments of one task on a thread pool. Environment i runs
// on thread i * T / N (a static partition); each environment owns all it
// writes, so the results are the same bits for any number of threads.
// Every argument is checked before any environment changes.
//
// Tasks on a model BatchStep can take (the fast presets' rigid car on a
// plane) step each thread's environments together, four cars to a SIMD
// group (physics/kernels/batch_step.hpp). Whether a task is batched depends on the
// task alone, and a car's arithmetic in a group does not depend on its lane
// or its neighbours, so the bits stay independent of the thread count.
#include "experiments/vec_env.hpp"

#include "accuracy/choice_cache.hpp"
#include "accuracy/pilot.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>

#include "experiments/env.hpp"
#include "experiments/snapshot.hpp"
#include "experiments/task_context.hpp"
#include "experiments/thread_pool.hpp"
#include "physics/kernels/batch_step.hpp"
#include "render/raster.hpp"
#include "scenario/object_reader.hpp"

namespace groundsim::experiments {
namespace {

constexpr std::uint64_t kSeedLimit = 1ull << 63;

void checkSeed(std::optional<std::uint64_t> seed) {
  if (seed && *seed >= kSeedLimit)
    throw ExperimentError("seed", "must be in [0, 2^63), got " + std::to_string(*seed));
}

// A refused curriculum as the experiments API words errors: the field is
// the first issue's pointer without its leading slash ("randomize/x").
ExperimentError curriculumError(const scenario::ScenarioError& e) {
  if (e.issues().empty()) return ExperimentError("randomize", e.lines("; "));
  const scenario::Issue& first = e.issues().front();
  const std::string field = first.path.empty() ? "randomize" : first.path.substr(1);
  return ExperimentError(field, e.issues().size() == 1 && e.omitted() == 0 ? first.message : e.lines("; "));
}

void checkBuffer(const void* p, const char* name) {
  if (!p) throw ExperimentError(name, "null buffer");
}

class VecEnv final : public BatchEnv {
 public:
  VecEnv(std::shared_ptr<const TaskContext> ctx, int num_envs, int threads)
      : ctx_(std::move(ctx)), layout_(ctx_->layout), pool_(threads) {
    layout_.num_envs = num_envs;
    envs_.reserve(static_cast<size_t>(num_envs));
    for (int i = 0; i < num_envs; ++i) envs_.push_back(std::make_unique<Env>(ctx_, static_cast<std::uint64_t>(i)));
    if (stepsBatched(*ctx_)) {
      const int threads = pool_.threads();
      lanes_.resize(static_cast<size_t>(threads));
      for (int t = 0; t < threads; ++t) {
        Lanes& l = lanes_[static_cast<size_t>(t)];
        l.step = std::make_unique<BatchStep>(ctx_->scene.built.model);
        l.cars.reserve(static_cast<size_t>(num_envs));  // no allocation while stepping
        l.envs.reserve(static_cast<size_t>(num_envs));
      }
    }
  }


  const Layout& layout() const override { return layout_; }

  void reset(std::optional<std::uint64_t> seed, float* obs) override {
    checkSeed(seed);
    checkBuffer(obs, "obs");
    Job job{this, obs, nullptr, nullptr, nullptr, seed, true};
    pool_.run(&VecEnv::runJob, &job);
  }

  void resetEnv(int env, std::optional<std::uint64_t> seed, float* obs_row) override {
    checkEnv(env);
    checkSeed(seed);
    checkBuffer(obs_row, "obs");
    envs_[static_cast<size_t>(env)]->reset(seed, obs_row);
  }

  void step(const float* actions, float* obs, double* rewards, std::uint8_t* terminated,
            std::uint8_t* truncated) override {
    checkBuffer(actions, "actions");
    checkBuffer(obs, "obs");
    checkBuffer(rewards, "rewards");
    checkBuffer(terminated, "terminated");
    checkBuffer(truncated, "truncated");
    const int n = layout_.rows(), k = layout_.actionSize();
    // refuse before anything moves: a NaN in the last row leaves every
    // environment as it was
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < k; ++j) {
        const float a = actions[static_cast<size_t>(i) * k + j];
        if (!std::isfinite(a))
          throw ExperimentError("actions[" + std::to_string(i) + "][" + std::to_string(j) + "]",
                                std::string("must be finite, got ") + (std::isnan(a) ? "nan" : a > 0 ? "inf" : "-inf") +
                                    " (" + layout_.action[static_cast<size_t>(j)] + ")");
      }
    const size_t per_env = static_cast<size_t>(layout_.num_agents) * k;
    for (size_t i = 0; i < envs_.size(); ++i) envs_[i]->setAction(actions + i * per_env);
    Job job{this, obs, rewards, terminated, truncated, std::nullopt, false};
    pool_.run(&VecEnv::runJob, &job);
  }

  EnvInfo info(int row) const override {
    if (row < 0 || row >= layout_.rows())
      throw ExperimentError("row", "must be in [0, " + std::to_string(layout_.rows()) + "), got " + std::to_string(row));
    return envs_[static_cast<size_t>(row / layout_.num_agents)]->info(row % layout_.num_agents);
  }

  std::string snapshot(int env) const override {
    checkEnv(env);
    return encodeSnapshot(layout_.scenario_hash, envs_[static_cast<size_t>(env)]->save());
  }

  void restore(int env, const std::string& bytes, float* obs_row) override {
    checkEnv(env);
    checkBuffer(obs_row, "obs");
    envs_[static_cast<size_t>(env)]->load(decodeSnapshot(bytes, layout_.scenario_hash), obs_row);
  }

  void setRandomization(int env, const std::string& randomize_json) override {
    if (env != -1) checkEnv(env);
    // each env's ranges may differ (an earlier curriculum): each env's new
    // ones are made from its own, all of them before any changes; the
    // parameter ends are validated once, with the first env's
    const size_t begin = env < 0 ? 0 : static_cast<size_t>(env), end = env < 0 ? envs_.size() : begin + 1;
    std::vector<scenario::Randomization> next;
    next.reserve(end - begin);
    try {
      for (size_t i = begin; i < end; ++i)
        next.push_back(curriculumRanges(*ctx_, randomize_json, envs_[i]->randomization(), i == begin));
    } catch (const scenario::ScenarioError& e) {
      throw curriculumError(e);
    }
    for (size_t i = begin; i < end; ++i) envs_[i]->setRandomization(std::move(next[i - begin]));
  }

  void render(int env, int width, int height, std::uint8_t* rgb) const override {
    checkEnv(env);
    checkBuffer(rgb, "rgb");
    if (width < 16 || height < 16 || width > 4096 || height > 4096)
      throw ExperimentError("render_size", "width and height must be in [16, 4096] px, got " + std::to_string(width) +
                                               " x " + std::to_string(height));
    // one raster for the batch (the calls take turns): a frame's buffers, not one per environment
    if (!raster_ || raster_->width() != width || raster_->height() != height)
      raster_ = std::make_unique<render::Raster>(width, height);
    envs_[static_cast<size_t>(env)]->render(*raster_, rgb);
  }

  void drawn(double* out) const override {
    checkBuffer(out, "drawn");
    const size_t d = static_cast<size_t>(layout_.drawnSize());
    for (size_t i = 0; i < envs_.size(); ++i) std::copy_n(envs_[i]->drawn().begin(), d, out + i * d);
  }

 private:
  struct Job {
    VecEnv* self;
    float* obs;
    double* rewards;
    std::uint8_t* terminated;
    std::uint8_t* truncated;
    std::optional<std::uint64_t> seed;
    bool reset;
  };

  static void runJob(void* p, int t) {
    const Job& j = *static_cast<const Job*>(p);
    VecEnv& v = *j.self;
    const long long n = v.layout_.num_envs, threads = v.pool_.threads();
    const long long begin = n * t / threads, end = n * (t + 1) / threads;
    // env i owns rows [i A, (i + 1) A): obs rows of m floats, one reward and two flags each
    const long long agents = v.layout_.num_agents;
    const size_t m = static_cast<size_t>(v.layout_.obsSize() * agents);
    if (!j.reset && !v.lanes_.empty()) {
      Lanes& l = v.lanes_[static_cast<size_t>(t)];
      l.cars.clear();
      l.envs.clear();
      for (long long i = begin; i < end; ++i) {
        Env& e = *v.envs_[static_cast<size_t>(i)];
        if (!e.beginStep(j.obs + static_cast<size_t>(i) * m, j.rewards + i, j.terminated + i, j.truncated + i)) continue;
        l.cars.push_back(&e.physicsState());
        l.envs.push_back(i);
      }
      l.step->step(std::span<State* const>(l.cars), v.ctx_->task().control_period);
      for (long long i : l.envs)
        v.envs_[static_cast<size_t>(i)]->finishStep(j.obs + static_cast<size_t>(i) * m, j.rewards + i,
                                                     j.terminated + i, j.truncated + i);
      return;
    }
    for (long long i = begin; i < end; ++i) {
      Env& e = *v.envs_[static_cast<size_t>(i)];
      float* row = j.obs + static_cast<size_t>(i) * m;
      if (j.reset) e.reset(j.seed ? std::optional<std::uint64_t>(*j.seed + static_cast<std::uint64_t>(i)) : std::nullopt, row);
      else e.step(row, j.rewards + i * agents, j.terminated + i * agents, j.truncated + i * agents);
    }
  }

  void checkEnv(int env) const {
    if (env < 0 || env >= layout_.num_envs)
      throw ExperimentError("env", "must be in [0, " + std::to_string(layout_.num_envs) + "), got " + std::to_string(env));
  }

  std::shared_ptr<const TaskContext> ctx_;
  Layout layout_;
  mutable std::unique_ptr<render::Raster> raster_;  // render(): made at the first frame, remade for another size
  std::vector<std::unique_ptr<Env>> envs_;
  ThreadPool pool_;
  // per thread, when the task is batched: its BatchStep (scratch of its own)
  // and the cars it steps this call
  struct Lanes {
    std::unique_ptr<BatchStep> step;
    std::vector<State*> cars;
    std::vector<long long> envs;
  };
  std::vector<Lanes> lanes_;
};

}  // namespace

std::unique_ptr<BatchEnv> makeVecEnv(const std::string& scenario_text, int num_envs, const VecEnvOptions& options) {
  if (num_envs < 1 || num_envs > options.max_envs)
    throw ExperimentError("num_envs", "must be in [1, " + std::to_string(options.max_envs) + "], got " +
                                          std::to_string(num_envs));
  if (options.num_threads < 0)
    throw ExperimentError("num_threads", "must be >= 0 (0: one per core), got " + std::to_string(options.num_threads));
  scenario::Scenario s = scenario::parseScenario(scenario_text, options.budget, options.files);
  // a tolerance: one pilot on the scene for all the environments (it sees
  // the scene's scripted controls, not the agents' actions to come)
  if (s.accuracy) {
    s = accuracy::ChoiceCache::shared()
            .choose(s, s.accuracy->tolerance, accuracy::pilotOptions(*s.accuracy, options.budget))
            .scenario;
  }
  // one batched step is bounded like a run: its integrator steps times
  // their estimated cost within the budget's work limit
  if (s.task) {
    const double work = static_cast<double>(num_envs) * s.task->control_period * std::max(1, s.options.substeps) *
                        scenario::estimateModelSize(s).work_per_step;
    if (work > options.budget.max_work)
      throw scenario::ScenarioError({scenario::Issue{
          "/task/control_period", "one step of " + std::to_string(num_envs) + " environments costs " +
                                      scenario::formatNumber(work) + " work units, at most " +
                                      scenario::formatNumber(options.budget.max_work) + " " +
                                      options.budget.flag("max-work")}});
  }
  auto ctx = makeTaskContext(std::move(s), options.budget, options.files);
  int threads = options.num_threads;
  if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, num_envs);
  return std::make_unique<VecEnv>(std::move(ctx), num_envs, threads);
}

std::unique_ptr<BatchEnv> makeVecEnvFromFile(const std::string& path, int num_envs, VecEnvOptions options) {
  nlohmann::json doc = scenario::loadScenarioDocument(path, options.budget);
  if (doc.is_object() && !doc.contains("name")) doc["name"] = std::filesystem::path(path).stem().string();
  options.files = scenario::FileAccess::local(std::filesystem::path(path).parent_path().string());
  return makeVecEnv(doc.dump(), num_envs, options);
}

}  // namespace groundsim::experiments
