// The `task` section (task_spec.hpp; docs/scenario.md, "Tasks"). Checked
// against the vehicles already read: the task's vehicle must exist, road-car
// features and actions need a road car, goal terms need a goal.
#include <algorithm>
#include <cmath>
#include <set>

#include "scenario/sections.hpp"

namespace groundsim::scenario {

const std::vector<std::string>& featureNames() {
  static const std::vector<std::string> names = {
      "position",     "heading",       "up_body",    "velocity_body", "angular_velocity_body",
      "speed",        "wheel_spin",    "wheel_contact", "wheel_slip", "suspension_travel",
      "height_samples", "goal_body",   "goal_distance", "previous_action", "time",
      "agents_body",  "track_ahead",   "track_pose", "track_curvature", "next_gate"};
  return names;
}

bool TaskSpec::usesTrack() const {
  for (Feature f : observation)
    if (f == Feature::TrackAhead || f == Feature::TrackPose || f == Feature::TrackCurvature || f == Feature::NextGate)
      return true;
  return reward.track_progress != 0.0 || reward.lap != 0.0 || reward.off_track != 0.0 || off_track_end > 0.0 ||
         laps > 0 || randomize.along_track;
}

namespace {

std::string knownList(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// [lo, hi] with lo <= hi, each in `each`.
std::array<double, 2> interval(ObjectReader& r, const std::string& key, Range each) {
  const std::vector<double> v = r.numbers(key, {0.0, 0.0}, each, 2, 2);
  if (v.size() == 2 && v[0] > v[1])
    r.issue(key, "expected [low, high] with low <= high, got [" + formatNumber(v[0]) + ", " + formatNumber(v[1]) + "]");
  if (v.size() != 2 || v[0] > v[1]) return {0.0, 0.0};
  return {v[0], v[1]};
}

std::array<double, 2> pair(ObjectReader& r, const std::string& key, std::array<double, 2> def, Range each) {
  const std::vector<double> v = r.numbers(key, {def[0], def[1]}, each, 2, 2);
  return v.size() == 2 ? std::array<double, 2>{v[0], v[1]} : def;
}

int vehicleIndex(ObjectReader& r, const std::vector<VehicleSpec>& vehicles) {
  const std::string def = vehicles.empty() ? std::string("car") : vehicles.front().name;
  const std::string name = r.string("vehicle", def);
  for (size_t i = 0; i < vehicles.size(); ++i)
    if (vehicles[i].name == name) return static_cast<int>(i);
  std::vector<std::string> names;
  for (const VehicleSpec& v : vehicles) names.push_back(v.name);
  r.issue("vehicle", "no vehicle named " + quote(name) + "; vehicles: " + knownList(names));
  return -1;
}

// `agents`: the names of the vehicles the agents drive, in the order of
// the batched rows; all cars of one kind (so that they share the spaces).
void readAgents(ObjectReader& r, const std::vector<VehicleSpec>& vehicles, TaskSpec& t) {
  if (r.has("vehicle")) r.issue("agents", "give `vehicle` (one agent) or `agents`, not both");
  else r.allow("vehicle");
  nlohmann::json* arr = r.array("agents");
  if (!arr) return;
  if (arr->empty() || arr->size() > static_cast<size_t>(kMaxAgents)) {
    r.issue("agents", "expected 1 to " + std::to_string(kMaxAgents) + " vehicle names, got " + std::to_string(arr->size()));
    return;
  }
  std::vector<std::string> names;
  for (const VehicleSpec& v : vehicles) names.push_back(v.name);
  std::vector<int> agents;
  for (size_t i = 0; i < arr->size(); ++i) {
    const std::string path = r.pathOf("agents") + "/" + std::to_string(i);
    const nlohmann::json& item = (*arr)[i];
    const auto it = item.is_string() ? std::find(names.begin(), names.end(), item.get<std::string>()) : names.end();
    if (it == names.end()) {
      r.issues().add(path, (item.is_string() ? "no vehicle named " + quote(item.get<std::string>())
                                             : "expected a vehicle name, got " + jsonTypeName(item)) +
                               "; vehicles: " + knownList(names));
      continue;
    }
    const int v = static_cast<int>(it - names.begin());
    if (std::find(agents.begin(), agents.end(), v) != agents.end()) {
      r.issues().add(path, "vehicle " + quote(*it) + " is listed twice");
      continue;
    }
    const VehicleSpec& spec = vehicles[static_cast<size_t>(v)];
    if (spec.lone_wheel) r.issues().add(path, "vehicle " + quote(*it) + " is a lone wheel; an agent drives a car");
    else if (!agents.empty() && spec.road_car != vehicles[static_cast<size_t>(agents[0])].road_car)
      r.issues().add(path, "vehicle " + quote(*it) + " is not of the first agent's kind (agents share their "
                           "observation and action spaces: all road cars, or all cars)");
    agents.push_back(v);
  }
  if (agents.size() == arr->size()) {
    t.agents = agents;
    t.vehicle = agents.front();
  }
}

void readObservation(ObjectReader& r, TaskSpec& t, const VehicleSpec* v) {
  if (!r.has("observation")) {
    r.issue("observation", "missing required key (an array of feature names; known: " + knownList(featureNames()) + ")");
    r.allow("observation");
    return;
  }
  nlohmann::json* arr = r.array("observation");
  if (!arr) return;
  if (arr->empty()) r.issue("observation", "must list at least one feature");
  const std::vector<std::string>& names = featureNames();
  std::set<std::string> seen;
  for (size_t i = 0; i < arr->size(); ++i) {
    const std::string path = r.pathOf("observation") + "/" + std::to_string(i);
    const nlohmann::json& item = (*arr)[i];
    if (!item.is_string()) {
      r.issues().add(path, "expected a feature name (a string), got " + jsonTypeName(item));
      continue;
    }
    const std::string name = item.get<std::string>();
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      r.issues().add(path, "unknown feature " + quote(name) + "; known: " + knownList(names));
      continue;
    }
    if (!seen.insert(name).second) {
      r.issues().add(path, "feature " + quote(name) + " is listed twice");
      continue;
    }
    if (name == "suspension_travel" && v && !v->road_car) {
      r.issues().add(path, "feature \"suspension_travel\" needs a vehicle of kind \"road_car\"");
      continue;
    }
    t.observation.push_back(static_cast<Feature>(it - names.begin()));
  }
}

void readHeightSamples(ObjectReader r, TaskSpec& t) {
  t.height_ahead = r.numbers("ahead", t.height_ahead, Range::closed(-1e4, 1e4), 1, kMaxHeightSamples);
  t.height_lateral = r.numbers("lateral", t.height_lateral, Range::closed(-1e4, 1e4), 1, kMaxHeightSamples);
  if (t.height_ahead.size() * t.height_lateral.size() > static_cast<size_t>(kMaxHeightSamples))
    r.issue("lateral", std::to_string(t.height_ahead.size() * t.height_lateral.size()) +
                           " samples (ahead x lateral), at most " + std::to_string(kMaxHeightSamples));
  r.finish();
}

void readAction(ObjectReader r, TaskSpec& t, const VehicleSpec* v) {
  const bool road = v && v->road_car;
  const std::string kind = r.choice("type", road ? "car_controls" : "wheel_torques", {"car_controls", "wheel_torques"});
  t.action = kind == "car_controls" ? ActionKind::CarControls : ActionKind::WheelTorques;
  t.handbrake = r.boolean("handbrake", false);
  t.max_torque = r.number("max_torque", 1.0, Range::positive(1e6));
  if (v && t.action == ActionKind::CarControls && !road)
    r.issue("type", "\"car_controls\" needs a vehicle of kind \"road_car\"; vehicle " + quote(v->name) +
                        " takes \"wheel_torques\"");
  if (t.handbrake && t.action != ActionKind::CarControls) r.issue("handbrake", "only with type \"car_controls\"");
  r.finish();
}

void readReward(ObjectReader r, RewardWeights& w) {
  const Range any = Range::closed(-1e6, 1e6);
  w.progress_to_goal = r.number("progress_to_goal", 0.0, any);
  w.progress_along = r.number("progress_along", 0.0, any);
  w.speed_tracking = r.number("speed_tracking", 0.0, any);
  w.effort = r.number("effort", 0.0, any);
  w.jerk = r.number("jerk", 0.0, any);
  w.tilt = r.number("tilt", 0.0, any);
  w.alive = r.number("alive", 0.0, any);
  w.goal = r.number("goal", 0.0, any);
  w.collision = r.number("collision", 0.0, any);
  w.track_progress = r.number("track_progress", 0.0, any);
  w.lap = r.number("lap", 0.0, any);
  w.off_track = r.number("off_track", 0.0, any);
  r.finish();
}

void readTermination(ObjectReader r, TaskSpec& t) {
  t.max_tilt_deg = r.number("max_tilt_deg", 0.0, Range::closed(0.0, 180.0));
  t.goal_radius = r.number("goal_radius", 0.0, Range::nonNegative(1e6));
  t.off_track_end = r.number("off_track", 0.0, Range::nonNegative(1e6));
  t.laps = r.integer("laps", 0, 0, 1000);
  if (r.has("region")) {
    ObjectReader region = r.object("region");
    const auto lo = region.numbers("min", {}, Range::any(), 2, 2);
    const auto hi = region.numbers("max", {}, Range::any(), 2, 2);
    if (!region.has("min") || !region.has("max")) region.issue(region.has("min") ? "max" : "min", "missing required key ([x, y])");
    else if (lo.size() == 2 && hi.size() == 2) {
      if (!(lo[0] < hi[0] && lo[1] < hi[1])) region.issue("max", "must exceed min in x and y");
      else {
        t.has_region = true;
        t.region_min = {lo[0], lo[1]};
        t.region_max = {hi[0], hi[1]};
      }
    }
    region.finish();
  } else {
    r.allow("region");
  }
  r.finish();
}

ParameterRange readParameter(ObjectReader& p) {
  ParameterRange pr;
  if (auto path = p.requiredString("path")) {
    pr.path = *path;
    const bool bad_chars = std::any_of(pr.path.begin(), pr.path.end(), [](unsigned char c) {
      return c < 0x20 || c == 0x7f || c == '=';
    });
    if (pr.path.empty() || pr.path.size() > 256 || bad_chars || pr.path.front() == '.' || pr.path.back() == '.' ||
        pr.path.find("..") != std::string::npos)
      p.issue("path", "expected a dotted scenario path such as \"ground.amplitude\", got " + quote(pr.path));
    else if (pr.path == "task" || pr.path.rfind("task.", 0) == 0)
      p.issue("path", "the task itself cannot be randomised, got " + quote(pr.path));
  }
  const auto range = interval(p, "range", Range::any());
  pr.lo = range[0];
  pr.hi = range[1];
  p.finish();
  return pr;
}

std::vector<ObjectReader> parameterReaders(ObjectReader& r) {
  if (!r.has("parameters")) r.allow("parameters");
  std::vector<ObjectReader> params = r.objects("parameters");
  if (params.size() > static_cast<size_t>(kMaxTaskParameters)) {
    r.issue("parameters", std::to_string(params.size()) + " parameters, at most " + std::to_string(kMaxTaskParameters));
    params.clear();
  }
  return params;
}

// The offsets' ranges within the schema's limits. A task's absent keys
// are filled in with [0, 0] (the validated document shows them); a
// curriculum's keep `current`.
void readOffsets(ObjectReader& r, const Randomization& current, Randomization& out, bool curriculum) {
  auto range = [&](const char* key, Range each, const std::array<double, 2>& was) {
    return r.has(key) || !curriculum ? interval(r, key, each) : (r.allow(key), was);
  };
  out.x = range("x", Range::closed(-1e4, 1e4), current.x);
  out.y = range("y", Range::closed(-1e4, 1e4), current.y);
  out.yaw_deg = range("yaw_deg", Range::closed(-360.0, 360.0), current.yaw_deg);
  out.speed = range("speed", Range::closed(-1e3, 1e3), current.speed);
  // a curriculum may change the range along the track of a task that has one
  if (r.has("track_s") && curriculum && !current.along_track)
    r.issue("track_s", "this task does not start along a track (its own randomize has no track_s)");
  else if (r.has("track_s")) {
    out.along_track = true;
    out.track_s = interval(r, "track_s", Range::closed(-1e6, 1e6));
  } else {
    r.allow("track_s");
  }
}

void readRandomize(ObjectReader r, TaskSpec& t) {
  readOffsets(r, Randomization{}, t.randomize, false);
  for (ObjectReader& p : parameterReaders(r)) t.randomize.parameters.push_back(readParameter(p));
  r.finish();
}

}  // namespace

TaskSpec readTask(ObjectReader r, const std::vector<VehicleSpec>& vehicles) {
  TaskSpec t;
  if (r.has("agents")) readAgents(r, vehicles, t);
  else {
    r.allow("agents");
    t.vehicle = vehicleIndex(r, vehicles);
    t.agents = {t.vehicle};
  }
  const VehicleSpec* v = t.vehicle >= 0 ? &vehicles[static_cast<size_t>(t.vehicle)] : nullptr;
  readObservation(r, t, v);
  readHeightSamples(r.object("height_samples"), t);
  {
    ObjectReader track = r.object("track");
    t.track_ahead = track.numbers("ahead", t.track_ahead, Range::closed(-1e4, 1e4), 1, kMaxTrackAhead);
    track.finish();
  }
  readAction(r.object("action"), t, v);
  t.control_period = r.integer("control_period", 1, 1, 100000);
  t.time_limit = r.number("time_limit", 0.0, Range::nonNegative(1e6));
  if (r.has("goal")) {
    const auto g = r.numbers("goal", {}, Range::any(), 2, 2);
    if (g.size() == 2) {
      t.has_goal = true;
      t.goal = {g[0], g[1]};
    }
  } else {
    r.allow("goal");
  }
  t.direction = pair(r, "direction", {1.0, 0.0}, Range::closed(-1e3, 1e3));
  const double dn = std::hypot(t.direction[0], t.direction[1]);
  if (dn <= 0.0) r.issue("direction", "must not be [0, 0]");
  else t.direction = {t.direction[0] / dn, t.direction[1] / dn};
  t.target_speed = r.number("target_speed", 0.0, Range::closed(-1e3, 1e3));
  t.speed_tolerance = r.number("speed_tolerance", 1.0, Range::positive(1e3));
  readReward(r.object("reward"), t.reward);
  readTermination(r.object("termination"), t);
  readRandomize(r.object("randomize"), t);
  r.finish();

  // what needs a goal, a road car, or another kind of vehicle
  const bool goal_used = t.reward.progress_to_goal != 0.0 || t.reward.goal != 0.0 || t.goal_radius > 0.0 ||
                         std::count(t.observation.begin(), t.observation.end(), Feature::GoalBody) ||
                         std::count(t.observation.begin(), t.observation.end(), Feature::GoalDistance);
  if (goal_used && !t.has_goal)
    r.issue("goal", "missing: goal features, progress_to_goal, the goal reward or goal_radius need a goal [x, y]");
  if (t.reward.goal != 0.0 && !(t.goal_radius > 0.0))
    r.issue("termination", "the goal reward needs termination.goal_radius > 0");
  if (v && v->lone_wheel)
    r.issue("vehicle", "vehicle " + quote(v->name) + " is a lone wheel; a task drives a car (kind \"car\" or \"road_car\")");
  return t;
}

Randomization readCurriculum(nlohmann::json randomize, const Randomization& current) {
  IssueList issues;
  if (!randomize.is_object()) {
    issues.add("/randomize", "expected an object such as {\"x\": [-2, 2]}, got " + std::string(randomize.type_name()));
    issues.throwIfAny();
  }
  Randomization out = current;
  {
    ObjectReader r(randomize, "/randomize", issues);
    readOffsets(r, current, out, true);
    for (ObjectReader& p : parameterReaders(r)) {
      // a curriculum's parameter says its new range: no default of [0, 0]
      if (!p.has("range")) p.issue("range", "missing required key ([low, high])");
      const ParameterRange pr = readParameter(p);
      auto it = std::find_if(out.parameters.begin(), out.parameters.end(),
                             [&](const ParameterRange& q) { return q.path == pr.path; });
      if (it != out.parameters.end()) {
        it->lo = pr.lo;
        it->hi = pr.hi;
      } else if (!pr.path.empty()) {
        std::string known;
        for (const ParameterRange& q : current.parameters) known += (known.empty() ? "" : ", ") + quote(q.path);
        p.issue("path", quote(pr.path) + " is not randomised by this task (a curriculum changes ranges, it adds "
                        "no parameter); the task's: " + (known.empty() ? "none" : known));
      }
    }
    r.finish();
  }
  issues.throwIfAny();
  return out;
}

}  // namespace groundsim::scenario
