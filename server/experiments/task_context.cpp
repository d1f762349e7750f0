// A validated scenario with a task -> the context its environments share:
// the base scene, the buffers' layout (names, bounds), the scenario hash.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "experiments/env.hpp"
#include "experiments/task_context.hpp"
#include "scenario/footprint.hpp"
#include "scenario/json_limits.hpp"
#include "scenario/object_reader.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::experiments {
namespace {

using scenario::Feature;
using scenario::TaskSpec;

constexpr float kInf = std::numeric_limits<float>::infinity();
const char* const kWheelNames[4] = {"fl", "fr", "rl", "rr"};

void add(Layout& l, const std::string& name, float lo = -kInf, float hi = kInf) {
  l.observation.push_back(name);
  l.observation_low.push_back(lo);
  l.observation_high.push_back(hi);
}

void addAction(Layout& l, const std::string& name, float lo, float hi) {
  l.action.push_back(name);
  l.action_low.push_back(lo);
  l.action_high.push_back(hi);
}

std::string hex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace

std::string scenarioHash(const nlohmann::json& document) {
  const std::string text = document.dump();
  // two FNV-1a lanes (different offsets) for 128 bits: a match by accident is not a concern
  return hex(fnv1a64(text.data(), text.size())) + hex(fnv1a64(text.data(), text.size(), 0x84222325cbf29ce4ull));
}

std::string overrideText(const std::string& path, double value) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  return path + "=" + buf;
}

Layout makeLayout(const scenario::Scenario& s, const scenario::Scene& scene) {
  const TaskSpec& t = *s.task;
  Layout l;
  l.dt = s.options.dt;
  l.control_period = t.control_period;
  l.time_limit = t.time_limit;
  for (size_t v = 0; v < s.vehicles.size(); ++v) {
    int n = 0;
    if (s.vehicles[v].road_car) n = 4;
    else
      for (int w : scene.cars[v].wheels) n += w >= 0 ? 1 : 0;
    l.wheel_counts.push_back(n);
  }
  // experiments/env.hpp kDrawn* order, per agent (named by it when there are several)
  for (int v : t.agents) {
    const std::string prefix = t.agents.size() > 1 ? s.vehicles[static_cast<size_t>(v)].name + "." : "";
    for (const char* d : {"x", "y", "yaw", "speed"}) l.drawn.push_back(prefix + d);
  }
  for (const scenario::ParameterRange& p : t.randomize.parameters) l.drawn.push_back(p.path);
  if (t.randomize.along_track) l.drawn.push_back("track_s");
  if (t.action == scenario::ActionKind::CarControls) {
    addAction(l, "throttle", 0.0f, 1.0f);
    addAction(l, "brake", 0.0f, 1.0f);
    addAction(l, "steer", -1.0f, 1.0f);
    if (t.handbrake) addAction(l, "handbrake", 0.0f, 1.0f);
  } else {
    const float m = static_cast<float>(t.max_torque);
    for (const char* w : kWheelNames) addAction(l, std::string("drive_torque.") + w, -m, m);
  }
  const char* xyz[3] = {"x", "y", "z"};
  for (Feature f : t.observation) {
    const std::string name = scenario::featureNames()[static_cast<size_t>(f)];
    switch (f) {
      case Feature::Position:
      case Feature::VelocityBody:
      case Feature::AngularVelocityBody:
        for (const char* c : xyz) add(l, name + "." + c);
        break;
      case Feature::UpBody:
        for (const char* c : xyz) add(l, name + "." + c, -1.0f, 1.0f);
        break;
      case Feature::Heading:
        add(l, name + ".cos", -1.0f, 1.0f);
        add(l, name + ".sin", -1.0f, 1.0f);
        break;
      case Feature::Speed:
      case Feature::GoalDistance:
      case Feature::Time:
        add(l, name, 0.0f, kInf);
        break;
      case Feature::WheelSpin:
      case Feature::WheelSlip:
      case Feature::SuspensionTravel:
        for (const char* w : kWheelNames) add(l, name + "." + w);
        break;
      case Feature::WheelContact:
        for (const char* w : kWheelNames) add(l, name + "." + w, 0.0f, 1.0f);
        break;
      case Feature::HeightSamples:
        for (size_t a = 0; a < t.height_ahead.size(); ++a)
          for (size_t b = 0; b < t.height_lateral.size(); ++b)
            add(l, name + "." + std::to_string(a * t.height_lateral.size() + b));
        break;
      case Feature::GoalBody:
        add(l, name + ".x");
        add(l, name + ".y");
        break;
      case Feature::PreviousAction:
        for (size_t k = 0; k < l.action.size(); ++k) add(l, name + "." + l.action[k], l.action_low[k], l.action_high[k]);
        break;
      case Feature::AgentsBody:
        // the others in agent order, from each agent's own view: "the k-th other"
        for (size_t k = 1; k < t.agents.size(); ++k)
          for (const char* c : {"x", "y", "vx", "vy"}) add(l, name + "." + std::to_string(k - 1) + "." + c);
        break;
      case Feature::TrackAhead:
        for (size_t k = 0; k < t.track_ahead.size(); ++k)
          for (const char* c : {"x", "y"}) add(l, name + "." + std::to_string(k) + "." + c);
        break;
      case Feature::TrackPose:
        add(l, name + ".offset");
        add(l, name + ".sin", -1.0f, 1.0f);
        add(l, name + ".cos", -1.0f, 1.0f);
        break;
      case Feature::TrackCurvature:
        for (size_t k = 0; k < t.track_ahead.size(); ++k) add(l, name + "." + std::to_string(k));
        break;
      case Feature::NextGate:
        add(l, name + ".x");
        add(l, name + ".y");
        break;
    }
  }
  for (int v : t.agents) l.agents.push_back(s.vehicles[static_cast<size_t>(v)].name);
  l.num_agents = static_cast<int>(t.agents.size());
  l.scenario_hash = scenarioHash(s.document);
  return l;
}

namespace {

// Both ends of one parameter range validate with the context's scenario;
// else ScenarioError at `pointer`.
void checkRangeEnds(const TaskContext& ctx, const scenario::ParameterRange& range, const std::string& pointer) {
  for (double v : {range.lo, range.hi}) {
    nlohmann::json doc = ctx.base_document;
    try {
      scenario::applyOverride(doc, overrideText(range.path, v), ctx.budget);
      scenario::parseScenario(std::move(doc), ctx.budget, ctx.files);
    } catch (const scenario::ScenarioError& e) {
      throw scenario::ScenarioError({scenario::Issue{pointer, "the value " + scenario::formatNumber(v) + " for " +
                                                                  scenario::quote(range.path) +
                                                                  " does not validate: " + e.lines("; ")}});
    }
  }
}

// Several agents: the drawn offsets must not bring two of them into each
// other (the scene builder would refuse that start at a reset, in the
// middle of a training run). Each may move by up to the largest offset in
// x and in y and turn by up to the largest drawn yaw. On the ground the
// builder compares footprint rectangles, and so does this check, grown by
// those moves (scenario::footprintsMayMeet): sedans stand 2.5 m abreast.
// Placed freely, the circles about the rectangles (the builder's test).
void checkAgentsApart(const scenario::Scenario& s, const std::vector<int>& agents, const scenario::Randomization& r,
                      const std::string& pointer) {
  const double mx = std::max(std::abs(r.x[0]), std::abs(r.x[1])), my = std::max(std::abs(r.y[0]), std::abs(r.y[1]));
  const double reach = std::hypot(mx, my);
  const double turn = std::max(std::abs(r.yaw_deg[0]), std::abs(r.yaw_deg[1])) * 3.14159265358979323846 / 180.0;
  for (size_t i = 0; i < agents.size(); ++i)
    for (size_t j = i + 1; j < agents.size(); ++j) {
      const scenario::VehicleSpec& a = s.vehicles[static_cast<size_t>(agents[i])];
      const scenario::VehicleSpec& b = s.vehicles[static_cast<size_t>(agents[j])];
      const Vec3 d = b.placement.position - a.placement.position;
      const double apart = std::hypot(d.x(), d.y());
      const bool flat = a.placement.on_ground && b.placement.on_ground;
      const double need = scenario::vehicleFootprint(a) + scenario::vehicleFootprint(b);
      const bool meet = flat ? scenario::footprintsMayMeet(a, b, mx, my, turn) : apart - 2.0 * reach < need;
      if (meet)
        throw scenario::ScenarioError({scenario::Issue{
            pointer, "agents " + scenario::quote(a.name) + " and " + scenario::quote(b.name) + " start " +
                         scenario::formatNumber(apart) + " m apart and may each be moved up to " +
                         scenario::formatNumber(mx) + " m in x and " + scenario::formatNumber(my) +
                         " m in y and turned up to " + scenario::formatNumber(turn * 180.0 / 3.14159265358979323846) +
                         " deg: they could be drawn into each other (" +
                         (flat ? std::string("their footprint rectangles would overlap")
                               : "their footprints need " + scenario::formatNumber(need) + " m") +
                         ")"}});
    }
}

}  // namespace

void checkParameterEnds(const TaskContext& ctx, const std::vector<scenario::ParameterRange>& ranges,
                        const std::string& pointer) {
  for (size_t i = 0; i < ranges.size(); ++i)
    checkRangeEnds(ctx, ranges[i], pointer + "/" + std::to_string(i) + "/range");
}

scenario::Randomization curriculumRanges(const TaskContext& ctx, const std::string& randomize_json,
                                         const scenario::Randomization& current, bool check_ends) {
  nlohmann::json doc;
  {
    scenario::IssueList issues;
    scenario::scanText(randomize_json, ctx.budget, issues);  // depth, size, duplicate keys
    issues.throwIfAny();
    doc = nlohmann::json::parse(randomize_json, nullptr, false);
    if (doc.is_discarded()) throw scenario::ScenarioError({scenario::Issue{"/randomize", "not valid JSON"}});
  }
  // where each path sits in the caller's list, for the pointer of a refusal
  std::vector<std::string> listed;
  if (doc.is_object() && doc.contains("parameters") && doc["parameters"].is_array())
    for (const nlohmann::json& p : doc["parameters"])
      listed.push_back(p.is_object() && p.contains("path") && p["path"].is_string() ? p["path"].get<std::string>() : "");
  scenario::Randomization next = scenario::readCurriculum(std::move(doc), current);
  checkAgentsApart(ctx.scenario, ctx.task().agents, next, "/randomize");
  // only the changed parameter ranges cost a validation
  for (size_t i = 0; check_ends && i < next.parameters.size(); ++i) {
    const scenario::ParameterRange& a = next.parameters[i];
    const scenario::ParameterRange& b = current.parameters[i];
    if (a.lo == b.lo && a.hi == b.hi) continue;
    const size_t k = static_cast<size_t>(std::find(listed.begin(), listed.end(), a.path) - listed.begin());
    checkRangeEnds(ctx, a, "/randomize/parameters/" + std::to_string(k) + "/range");
  }
  return next;
}

nlohmann::json rangesJson(const scenario::Randomization& r) {
  nlohmann::json j = {{"x", r.x}, {"y", r.y}, {"yaw_deg", r.yaw_deg}, {"speed", r.speed}};
  j["parameters"] = nlohmann::json::array();
  for (const scenario::ParameterRange& p : r.parameters)
    j["parameters"].push_back({{"path", p.path}, {"range", {p.lo, p.hi}}});
  return j;
}

std::shared_ptr<const TaskContext> makeTaskContext(scenario::Scenario s, const scenario::Budget& budget,
                                                    const scenario::FileAccess& files) {
  if (!s.task)
    throw scenario::ScenarioError({scenario::Issue{"/task", "missing: an experiment needs a task section"}});
  auto ctx = std::make_shared<TaskContext>();
  ctx->scene = scenario::buildScene(s);
  ctx->budget = budget;
  ctx->files = files;
  ctx->base_document = s.document;
  ctx->base_document.erase("task");
  const TaskSpec& t = *s.task;
  checkParameterEnds(*ctx, t.randomize.parameters, "/task/randomize/parameters");
  checkAgentsApart(s, t.agents, t.randomize, "/task/randomize");
  for (int v : t.agents) {
    Agent a;
    a.vehicle = v;
    a.body = ctx->scene.cars.at(static_cast<size_t>(v)).body;
    a.wheels = ctx->scene.cars[static_cast<size_t>(v)].wheels;
    for (size_t c = 0; c < ctx->scene.built.model->road_cars.size(); ++c)
      if (ctx->scene.built.model->road_cars[c].vehicle == ctx->scene.cars[static_cast<size_t>(v)].vehicle)
        a.road_car = static_cast<int>(c);
    ctx->agents.push_back(a);
  }
  if (t.usesTrack()) ctx->track = std::make_shared<const drivers::TrackCourse>(*s.race);  // validated: s.race has a line
  ctx->control_dt = s.options.dt * t.control_period;
  ctx->max_steps = t.time_limit > 0.0 ? static_cast<std::int64_t>(std::ceil(t.time_limit / ctx->control_dt - 1e-9)) : 0;
  ctx->layout = makeLayout(s, ctx->scene);
  ctx->scenario = std::move(s);
  return ctx;
}

}  // namespace groundsim::experiments
