#include "race/race.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

namespace groundsim::race {
namespace {

double cross2(const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; }
Vec2 sub(const Vec2& a, const Vec2& b) { return {a[0] - b[0], a[1] - b[1]}; }
double dot2(const Vec2& a, const Vec2& b) { return a[0] * b[0] + a[1] * b[1]; }
double norm2(const Vec2& a) { return std::hypot(a[0], a[1]); }

// below this a car is standing, its heading no notice's business
constexpr double kMovingSpeed = 1.0;          // m/s
// cos of the angle to the track beyond which a car goes against it / with it
constexpr double kAgainstCos = -0.5, kWithCos = 0.5;
// back on the track this far inside the edge (no flicker along it)
constexpr double kTrackHysteresis = 0.25;     // m
// a respawned car is put this far past its gate (not on the line)
constexpr double kRespawnPastGate = 2.0;      // m
// the nearest centre-line segment is looked for this many segments either
// side of the last one; the whole line when that finds the car off track
constexpr int kSegmentWindow = 16;

double segmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = sub(b, a), ap = sub(p, a);
  const double len2 = dot2(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(dot2(ap, ab) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(ap[0] - s * ab[0], ap[1] - s * ab[1]);
}

}  // namespace

const char* kindName(EventKind k) {
  switch (k) {
    case EventKind::Go: return "go";
    case EventKind::Start: return "start";
    case EventKind::Gate: return "gate";
    case EventKind::Lap: return "lap";
    case EventKind::Finish: return "finish";
    case EventKind::WrongWay: return "wrong_way";
    case EventKind::OffTrack: return "off_track";
    case EventKind::Respawn: return "respawn";
  }
  return "?";
}

int crossing(const Vec2& p0, const Vec2& p1, const Vec2& a, const Vec2& b, double* s_out) {
  const Vec2 d = sub(p1, p0), e = sub(b, a), w = sub(a, p0);
  const double denom = cross2(d, e);
  if (denom == 0.0 || !std::isfinite(denom)) return 0;  // not moving, or along the gate
  const double s = cross2(w, e) / denom, u = cross2(w, d) / denom;
  if (!(s >= 0.0 && s < 1.0 && u >= 0.0 && u <= 1.0)) return 0;
  *s_out = s;
  // forward is rot90(e) = (-e.y, e.x): d . forward = -cross(d, e)
  return denom < 0.0 ? 1 : -1;
}

Race::Race(scenario::RaceSpec spec, int cars) : spec_(std::move(spec)), cars_(static_cast<std::size_t>(cars)) {
  reset();
}

void Race::reset() {
  for (std::size_t k = 0; k < cars_.size(); ++k) {
    cars_[k] = CarStanding{};
    cars_[k].car = static_cast<int>(k);
    cars_[k].position = static_cast<int>(k) + 1;
  }
  against_.assign(cars_.size(), 0.0);
  near_segment_.assign(cars_.size(), 0);
  finished_ = 0;
  went_ = false;
}

bool Race::over() const { return !cars_.empty() && finished_ == static_cast<int>(cars_.size()); }

Vec2 Race::gateCentre(int g) const {
  const auto& gate = spec_.gates.at(static_cast<std::size_t>(g));
  return {0.5 * (gate.left[0] + gate.right[0]), 0.5 * (gate.left[1] + gate.right[1])};
}

Vec2 Race::gateForward(int g) const {
  const auto& gate = spec_.gates.at(static_cast<std::size_t>(g));
  const Vec2 e = sub(gate.right, gate.left);
  const double n = norm2(e);
  return {-e[1] / n, e[0] / n};
}

std::vector<RaceEvent> Race::step(double t0, double t1, const std::vector<Vec2>& before,
                                  const std::vector<Vec2>& after) {
  std::vector<RaceEvent> out;
  if (!went_ && t1 >= spec_.countdown) {
    went_ = true;
    RaceEvent e;
    e.kind = EventKind::Go;
    e.t = spec_.countdown;
    out.push_back(e);
  }
  if (!went_ || spec_.gates.size() < 2) return out;
  const int n = static_cast<int>(spec_.gates.size());
  const std::size_t cars = std::min({cars_.size(), before.size(), after.size()});
  for (std::size_t k = 0; k < cars; ++k) {
    CarStanding& c = cars_[k];
    const Vec2 &p0 = before[k], &p1 = after[k];
    if (!(std::isfinite(p0[0]) && std::isfinite(p0[1]) && std::isfinite(p1[0]) && std::isfinite(p1[1]))) continue;
    if (!c.finished) {
      // the next gate, and the one after it should the same step reach it too
      double from = 0.0;  // fraction of the step already used
      for (int guard = 0; guard < n && !c.finished; ++guard) {
        const Vec2 q0{p0[0] + from * (p1[0] - p0[0]), p0[1] + from * (p1[1] - p0[1])};
        const auto& gate = spec_.gates[static_cast<std::size_t>(c.next_gate)];
        double s = 0.0;
        if (crossing(q0, p1, gate.left, gate.right, &s) != 1) break;
        const double f = from + s * (1.0 - from);
        // a crossing before go (a car past the line when released) does not count
        const double tc = std::max(t0 + f * (t1 - t0), spec_.countdown);
        cross(static_cast<int>(k), c.next_gate, tc, out);
        from = f + 1e-12;
        if (from >= 1.0) break;
      }
    }
    wrongWay(static_cast<int>(k), p0, p1, t0, t1, out);
    offTrack(static_cast<int>(k), p1, t1, out);
  }
  return out;
}

void Race::cross(int k, int g, double tc, std::vector<RaceEvent>& out) {
  CarStanding& c = cars_[static_cast<std::size_t>(k)];
  const int n = static_cast<int>(spec_.gates.size());
  RaceEvent e;
  e.car = k;
  e.t = tc;
  e.gate = g;
  e.lap = c.laps_done + 1;
  c.last_cross = tc;
  bool lap_done = false;
  if (!c.started) {  // g == 0
    c.started = true;
    c.lap_start = tc;
    c.splits.clear();
    e.kind = EventKind::Start;
    out.push_back(e);
    c.next_gate = 1;
    return;
  }
  if (g == 0) {
    lap_done = true;  // a circuit's line
  } else {
    e.kind = EventKind::Gate;
    e.time = tc - c.lap_start;
    c.splits.push_back(e.time);
    out.push_back(e);
    c.next_gate = g + 1;
    if (c.next_gate == n) {
      c.next_gate = 0;
      lap_done = !spec_.circuit;  // a stage ends at its last gate
    }
    if (!lap_done) return;
  }
  // a lap completed at tc
  RaceEvent lap = e;
  lap.kind = EventKind::Lap;
  lap.gate = g;
  lap.time = tc - c.lap_start;
  c.last_lap = lap.time;
  c.laps_done += 1;
  if (c.best_lap == 0.0 || lap.time < c.best_lap) {
    c.best_lap = lap.time;
    c.best_splits = c.splits;
    lap.best = true;
  }
  out.push_back(lap);
  c.lap_start = tc;
  c.splits.clear();
  c.next_gate = spec_.circuit ? 1 : 0;
  if (c.laps_done >= spec_.laps) {
    c.finished = true;
    c.finish_time = tc - spec_.countdown;
    ++finished_;
    RaceEvent fin = e;
    fin.kind = EventKind::Finish;
    fin.lap = c.laps_done;
    fin.time = c.finish_time;
    fin.position = finished_;
    c.position = finished_;
    out.push_back(fin);
  }
}

void Race::wrongWay(int k, const Vec2& p0, const Vec2& p1, double t0, double t1, std::vector<RaceEvent>& out) {
  CarStanding& c = cars_[static_cast<std::size_t>(k)];
  const double dt = t1 - t0;
  if (!(dt > 0.0)) return;
  const Vec2 d = sub(p1, p0);
  const double speed = norm2(d) / dt;
  Vec2 dir;
  if (!c.started || c.finished) {
    dir = gateForward(0);
  } else {
    const int n = static_cast<int>(spec_.gates.size());
    const int prev = (c.next_gate + n - 1) % n;
    dir = sub(gateCentre(c.next_gate), gateCentre(prev));
    const double len = norm2(dir);
    if (len > 0.0) dir = {dir[0] / len, dir[1] / len};
    else dir = gateForward(c.next_gate);
  }
  const double cosine = speed > kMovingSpeed ? dot2(d, dir) / norm2(d) : 0.0;
  if (speed > kMovingSpeed && cosine < kAgainstCos) against_[static_cast<std::size_t>(k)] += dt;
  else if (cosine > 0.0) against_[static_cast<std::size_t>(k)] = 0.0;
  RaceEvent e;
  e.kind = EventKind::WrongWay;
  e.car = k;
  e.t = t1;
  e.gate = c.next_gate;
  e.lap = c.laps_done + 1;
  if (!c.wrong_way && against_[static_cast<std::size_t>(k)] >= spec_.wrong_way_time - 1e-9) {
    c.wrong_way = e.on = true;
    out.push_back(e);
  } else if (c.wrong_way && cosine > kWithCos) {
    c.wrong_way = e.on = false;
    out.push_back(e);
  }
}

double Race::distanceToCentreline(int k, const Vec2& p) {
  const auto& line = spec_.centerline;
  const int segs = static_cast<int>(line.size()) - (spec_.circuit ? 0 : 1);
  if (segs <= 0) return 0.0;
  auto dist = [&](int i) {
    const int j = (i + 1) % static_cast<int>(line.size());
    return segmentDistance(p, line[static_cast<std::size_t>(i)], line[static_cast<std::size_t>(j)]);
  };
  int& near = near_segment_[static_cast<std::size_t>(k)];
  double best = std::numeric_limits<double>::infinity();
  int best_i = near;
  for (int o = -kSegmentWindow; o <= kSegmentWindow; ++o) {
    const int i = ((near + o) % segs + segs) % segs;
    const double d = dist(i);
    if (d < best) best = d, best_i = i;
  }
  if (best > spec_.half_width - kTrackHysteresis)
    for (int i = 0; i < segs; ++i) {
      const double d = dist(i);
      if (d < best) best = d, best_i = i;
    }
  near = best_i;
  return best;
}

void Race::offTrack(int k, const Vec2& p, double t, std::vector<RaceEvent>& out) {
  if (spec_.centerline.size() < 2 || spec_.half_width <= 0.0) return;
  CarStanding& c = cars_[static_cast<std::size_t>(k)];
  const double d = distanceToCentreline(k, p);
  RaceEvent e;
  e.kind = EventKind::OffTrack;
  e.car = k;
  e.t = t;
  e.gate = c.next_gate;
  e.lap = c.laps_done + 1;
  if (!c.off_track && d > spec_.half_width) {
    c.off_track = e.on = true;
    out.push_back(e);
  } else if (c.off_track && d < spec_.half_width - kTrackHysteresis) {
    c.off_track = e.on = false;
    out.push_back(e);
  }
}

std::optional<Pose> Race::respawnPose(int car) const {
  const CarStanding& c = cars_.at(static_cast<std::size_t>(car));
  const int n = static_cast<int>(spec_.gates.size());
  if (c.started && n >= 2) {
    const int last = (c.next_gate + n - 1) % n;
    const Vec2 centre = gateCentre(last), fwd = gateForward(last);
    Pose p;
    p.position = {centre[0] + kRespawnPastGate * fwd[0], centre[1] + kRespawnPastGate * fwd[1]};
    p.yaw = std::atan2(fwd[1], fwd[0]);
    p.gate = last;
    return p;
  }
  if (static_cast<std::size_t>(car) < spec_.grid.size()) {
    Pose p;
    p.position = spec_.grid[static_cast<std::size_t>(car)].position;
    p.yaw = spec_.grid[static_cast<std::size_t>(car)].yaw;
    return p;
  }
  return std::nullopt;
}

std::vector<RaceEvent> Race::respawned(int car, const Pose& at, double t) {
  std::vector<RaceEvent> out;
  CarStanding& c = cars_.at(static_cast<std::size_t>(car));
  c.protected_until = t + spec_.respawn_protection;
  against_[static_cast<std::size_t>(car)] = 0.0;
  RaceEvent e;
  e.car = car;
  e.t = t;
  e.gate = at.gate;
  e.lap = c.laps_done + 1;
  if (c.wrong_way) {
    c.wrong_way = false;
    e.kind = EventKind::WrongWay;
    out.push_back(e);
  }
  if (c.off_track) {
    c.off_track = false;
    e.kind = EventKind::OffTrack;
    out.push_back(e);
  }
  e.kind = EventKind::Respawn;
  e.time = c.protected_until;
  out.push_back(e);
  return out;
}

std::vector<CarStanding> Race::leaderboard() const {
  std::vector<CarStanding> v = cars_;
  const int n = static_cast<int>(spec_.gates.size());
  auto progress = [&](const CarStanding& c) {
    if (!c.started) return 0;
    const int passed = c.next_gate == 0 ? n : c.next_gate;  // gates of this lap behind it
    return 1 + c.laps_done * n + passed;
  };
  std::stable_sort(v.begin(), v.end(), [&](const CarStanding& a, const CarStanding& b) {
    if (a.finished != b.finished) return a.finished;
    if (a.finished) return a.finish_time < b.finish_time;
    const int pa = progress(a), pb = progress(b);
    if (pa != pb) return pa > pb;
    return a.last_cross < b.last_cross;
  });
  for (std::size_t i = 0; i < v.size(); ++i) v[i].position = static_cast<int>(i) + 1;
  return v;
}

namespace {
std::string nameOf(int car, const std::vector<std::string>& names) {
  return car >= 0 && static_cast<std::size_t>(car) < names.size() ? names[static_cast<std::size_t>(car)]
                                                                   : "car " + std::to_string(car);
}
}  // namespace

std::string Race::reason(const RaceEvent& e, const std::vector<std::string>& names) {
  nlohmann::json j;
  j["type"] = kindName(e.kind);
  j["t"] = e.t;
  if (e.car >= 0) {
    j["car"] = e.car;
    j["name"] = nameOf(e.car, names);
    j["lap"] = e.lap;
    j["gate"] = e.gate;
  }
  switch (e.kind) {
    case EventKind::Gate: j["split"] = e.time; break;
    case EventKind::Lap: j["lap_time"] = e.time; j["best"] = e.best; break;
    case EventKind::Finish: j["race_time"] = e.time; j["position"] = e.position; break;
    case EventKind::WrongWay:
    case EventKind::OffTrack: j["on"] = e.on; break;
    case EventKind::Respawn: j["protected_until"] = e.time; break;
    default: break;
  }
  return "race: " + j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string Race::standingsReason(double t, const std::vector<std::string>& names) const {
  nlohmann::json j;
  j["type"] = "standings";
  j["t"] = t;
  j["laps"] = spec_.laps;
  j["gates"] = spec_.gates.size();
  nlohmann::json cars = nlohmann::json::array();
  for (const CarStanding& c : leaderboard()) {
    nlohmann::json o;
    o["car"] = c.car;
    o["name"] = nameOf(c.car, names);
    o["position"] = c.position;
    o["laps_done"] = c.laps_done;
    o["next_gate"] = c.next_gate;
    o["started"] = c.started;
    o["lap_start"] = c.lap_start;
    o["last_lap"] = c.last_lap;
    o["best_lap"] = c.best_lap;
    o["finished"] = c.finished;
    o["race_time"] = c.finish_time;
    cars.push_back(std::move(o));
  }
  j["cars"] = std::move(cars);
  return "race: " + j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string Race::layoutReason(const std::vector<std::string>& names) const {
  nlohmann::json j;
  j["type"] = "race";
  j["laps"] = spec_.laps;
  j["circuit"] = spec_.circuit;
  j["go"] = spec_.countdown;
  j["cars"] = names;
  nlohmann::json gates = nlohmann::json::array();
  for (const auto& g : spec_.gates) gates.push_back({g.left[0], g.left[1], g.right[0], g.right[1]});
  j["gates"] = std::move(gates);
  return "race: " + j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// ---- progress, for a session's snapshot -------------------------------------

namespace {
nlohmann::json standingJson(const CarStanding& c) {
  return {{"car", c.car}, {"position", c.position}, {"started", c.started}, {"finished", c.finished},
          {"laps_done", c.laps_done}, {"next_gate", c.next_gate}, {"lap_start", c.lap_start},
          {"last_lap", c.last_lap}, {"best_lap", c.best_lap}, {"finish_time", c.finish_time},
          {"last_cross", c.last_cross}, {"splits", c.splits}, {"best_splits", c.best_splits},
          {"wrong_way", c.wrong_way}, {"off_track", c.off_track}, {"protected_until", c.protected_until}};
}

CarStanding standingFrom(const nlohmann::json& j) {
  CarStanding c;
  c.car = j.at("car").get<int>();
  c.position = j.at("position").get<int>();
  c.started = j.at("started").get<bool>();
  c.finished = j.at("finished").get<bool>();
  c.laps_done = j.at("laps_done").get<int>();
  c.next_gate = j.at("next_gate").get<int>();
  c.lap_start = j.at("lap_start").get<double>();
  c.last_lap = j.at("last_lap").get<double>();
  c.best_lap = j.at("best_lap").get<double>();
  c.finish_time = j.at("finish_time").get<double>();
  c.last_cross = j.at("last_cross").get<double>();
  c.splits = j.at("splits").get<std::vector<double>>();
  c.best_splits = j.at("best_splits").get<std::vector<double>>();
  c.wrong_way = j.at("wrong_way").get<bool>();
  c.off_track = j.at("off_track").get<bool>();
  c.protected_until = j.at("protected_until").get<double>();
  return c;
}
}  // namespace

// Doubles go as JSON numbers (nlohmann writes the shortest text that reads
// back to the same double), so a restored race times the next lap to the bit.
nlohmann::json Race::progress() const {
  nlohmann::json cars = nlohmann::json::array();
  for (const CarStanding& c : cars_) cars.push_back(standingJson(c));
  return {{"cars", cars}, {"against", against_}, {"near_segment", near_segment_}, {"finished", finished_},
          {"went", went_}};
}

std::string Race::restore(const nlohmann::json& j) {
  try {
    std::vector<CarStanding> cars;
    for (const nlohmann::json& c : j.at("cars")) cars.push_back(standingFrom(c));
    std::vector<double> against = j.at("against").get<std::vector<double>>();
    std::vector<int> near = j.at("near_segment").get<std::vector<int>>();
    if (cars.size() != cars_.size() || against.size() != against_.size() || near.size() != near_segment_.size())
      return "the race's progress is of " + std::to_string(cars.size()) + " cars, this race has " +
             std::to_string(cars_.size());
    for (std::size_t k = 0; k < cars.size(); ++k)
      if (cars[k].car != static_cast<int>(k) || cars[k].next_gate < 0 ||
          cars[k].next_gate >= static_cast<int>(std::max<std::size_t>(1, spec_.gates.size())))
        return "the race's progress: car " + std::to_string(k) + " does not fit this race";
    cars_ = std::move(cars);
    against_ = std::move(against);
    near_segment_ = std::move(near);
    finished_ = j.at("finished").get<int>();
    went_ = j.at("went").get<bool>();
    return "";
  } catch (const std::exception& e) {
    return std::string("the race's progress: ") + e.what();
  }
}

}  // namespace groundsim::race
