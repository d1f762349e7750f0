// The `race` section: gates, laps, grid, boundary (race_spec.hpp).
#include <cmath>

#include "scenario/race_spec.hpp"
#include "scenario/sections.hpp"

namespace groundsim::scenario {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
// a gate narrower than this cannot be driven through; wider than this is a typo
constexpr double kMinGateWidth = 0.5;   // m
constexpr double kMaxGateWidth = 1000.0;
// the track's horizontal extent: 100 km
constexpr double kMaxCoordinate = 1e5;  // m

std::array<double, 2> xy(ObjectReader& r, const std::string& key, bool* ok) {
  const Range each = Range::closed(-kMaxCoordinate, kMaxCoordinate);
  if (!r.has(key)) {
    r.allow(key);
    r.issue(key, "missing required key (an array [x, y] in m)");
    *ok = false;
    return {0.0, 0.0};
  }
  const std::size_t before = r.issues().size();
  const std::vector<double> v = r.numbers(key, {0.0, 0.0}, each, 2, 2);
  if (r.issues().size() != before) *ok = false;
  return {v[0], v[1]};
}

// an array read element by element, refused whole (one line) when longer
// than `most`, before any element is read
nlohmann::json* boundedArray(ObjectReader& r, const std::string& key, std::size_t most, const char* what) {
  const nlohmann::json* peeked = r.peek(key);
  if (peeked && peeked->is_array() && peeked->size() > most) {
    r.allow(key);
    r.issue(key, std::to_string(peeked->size()) + " " + what + ", at most " + std::to_string(most));
    return nullptr;
  }
  return r.array(key);
}

RaceGate readGate(ObjectReader g) {
  RaceGate gate;
  if (!g.valid()) return gate;
  bool ok = true;
  const bool posts = g.has("left") || g.has("right");
  const bool centred = g.has("center") || g.has("width") || g.has("heading_deg");
  if (posts && centred) {
    g.issue("left", "give either \"left\" and \"right\" (the posts) or \"center\", \"width\" and \"heading_deg\", "
                    "not both");
    g.allow("center");
    g.allow("width");
    g.allow("heading_deg");
    g.allow("left");
    g.allow("right");
    g.finish();
    return gate;
  }
  if (centred) {
    const auto c = xy(g, "center", &ok);
    const auto width = g.requiredNumber("width", Range::closed(kMinGateWidth, kMaxGateWidth));
    const auto heading = g.requiredNumber("heading_deg", Range::closed(-360.0, 360.0));
    if (!width || !heading || !ok) {
      g.finish();
      return gate;
    }
    // forward (cos h, sin h); left of it is (-sin h, cos h)
    const double h = *heading * kDegToRad, half = 0.5 * *width;
    gate.left = {c[0] - half * std::sin(h), c[1] + half * std::cos(h)};
    gate.right = {c[0] + half * std::sin(h), c[1] - half * std::cos(h)};
  } else {
    gate.left = xy(g, "left", &ok);
    gate.right = xy(g, "right", &ok);
    if (ok) {
      const double w = std::hypot(gate.right[0] - gate.left[0], gate.right[1] - gate.left[1]);
      if (!(w >= kMinGateWidth && w <= kMaxGateWidth))
        g.issue("right", "the gate is " + formatNumber(w) + " m wide (left to right), must be in [" +
                             formatNumber(kMinGateWidth) + ", " + formatNumber(kMaxGateWidth) + "] m");
    }
  }
  g.finish();
  return gate;
}

}  // namespace

RaceSpec readRace(ObjectReader r, int vehicles) {
  RaceSpec s;
  const RaceSpec def;
  if (!r.valid()) return s;
  s.laps = r.integer("laps", def.laps, 1, kMaxRaceLaps);
  s.circuit = r.boolean("circuit", def.circuit);
  s.countdown = r.number("countdown", def.countdown, Range::closed(0.0, 60.0));
  s.respawn_protection = r.number("respawn_protection", def.respawn_protection, Range::closed(0.0, 60.0));
  s.wrong_way_time = r.number("wrong_way_time", def.wrong_way_time, Range::closed(0.05, 60.0));
  s.bots = r.integer("bots", def.bots, 0, kMaxGridSlots);
  if (s.bots > vehicles)
    r.issue("bots", std::to_string(s.bots) + " bots for " + std::to_string(vehicles) +
                        " vehicles: a bot drives one of the scenario's vehicles (the last ones)");
  if (r.has("bot_policy")) {
    if (const auto name = r.requiredString("bot_policy")) s.bot_policy = *name;
    if (s.bots == 0) r.issue("bot_policy", "names a driver for no bots (race.bots is 0)");
  } else {
    r.allow("bot_policy");
  }
  if (r.has("bot_skill")) s.bot_skill = r.number("bot_skill", def.bot_skill, Range::closed(0.2, 1.0));
  else r.allow("bot_skill");
  if (!s.circuit && s.laps != 1) r.issue("laps", "a stage (\"circuit\": false) is driven once: laps must be 1, got " +
                                                     std::to_string(s.laps));

  if (!r.has("gates")) {
    r.allow("gates");
    r.issue("gates", "missing required key (an array of at least 2 gates)");
  } else if (nlohmann::json* gates = boundedArray(r, "gates", kMaxRaceGates, "gates")) {
    if (gates->size() < 2) r.issue("gates", "at least 2 gates, got " + std::to_string(gates->size()));
    for (std::size_t i = 0; i < gates->size(); ++i)
      s.gates.push_back(readGate(ObjectReader((*gates)[i], r.pathOf("gates") + "/" + std::to_string(i), r.issues())));
  }

  if (nlohmann::json* grid = boundedArray(r, "grid", kMaxGridSlots, "grid slots")) {
    for (std::size_t i = 0; i < grid->size(); ++i) {
      ObjectReader g((*grid)[i], r.pathOf("grid") + "/" + std::to_string(i), r.issues());
      if (!g.valid()) continue;
      bool ok = true;
      GridSlot slot;
      slot.position = xy(g, "position", &ok);
      slot.yaw = g.number("heading_deg", 0.0, Range::closed(-360.0, 360.0)) * kDegToRad;
      g.finish();
      s.grid.push_back(slot);
    }
    if (!grid->empty() && static_cast<int>(grid->size()) < vehicles)
      r.issue("grid", std::to_string(grid->size()) + " slots for " + std::to_string(vehicles) +
                          " vehicles: give one slot per vehicle (or none: each keeps its initial position)");
  }

  if (r.has("track")) {
    ObjectReader t = r.object("track");
    if (t.valid()) {
      s.half_width = t.requiredNumber("half_width", Range::closed(0.5, 1000.0)).value_or(0.0);
      if (!t.has("centerline")) {
        t.allow("centerline");
        t.issue("centerline", "missing required key (an array of at least 2 points [x, y])");
      } else if (nlohmann::json* line = boundedArray(t, "centerline", kMaxCenterlinePoints, "points")) {
        if (line->size() < 2) t.issue("centerline", "at least 2 points, got " + std::to_string(line->size()));
        const Range each = Range::closed(-kMaxCoordinate, kMaxCoordinate);
        for (std::size_t i = 0; i < line->size(); ++i) {
          const std::string path = t.pathOf("centerline") + "/" + std::to_string(i);
          const nlohmann::json& p = (*line)[i];
          if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
            t.issues().add(path, "expected [x, y] (two numbers), got " + jsonTypeName(p) +
                                     (p.is_array() ? " of " + std::to_string(p.size()) : std::string()));
            continue;
          }
          const double x = p[0].get<double>(), y = p[1].get<double>();
          bool bad = false;
          for (int k = 0; k < 2; ++k)
            if (auto why = each.violation(k ? y : x)) {
              t.issues().add(path + "/" + std::to_string(k), *why);
              bad = true;
            }
          if (!bad) s.centerline.push_back({x, y});
        }
      }
      t.finish();
    }
  } else {
    r.allow("track");
  }
  r.finish();
  return s;
}

}  // namespace groundsim::scenario
