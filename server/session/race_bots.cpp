#include "session/race_bots.hpp"

#include <algorithm>
#include <cmath>

#include "drivers/lap_run.hpp"
#include "drivers/policy_driver.hpp"
#include "scenario/scenario_error.hpp"

namespace groundsim::session {
namespace {

std::shared_ptr<const drivers::Policy> loadPolicy(const scenario::RaceSpec& race) {
  try {
    if (!race.bot_policy_text) throw drivers::PolicyError("the file was not read with the scenario");
    return std::make_shared<const drivers::Policy>(drivers::Policy::parse(*race.bot_policy_text));
  } catch (const drivers::PolicyError& e) {
    throw scenario::ScenarioError({scenario::Issue{"/race/bot_policy", e.what()}});
  }
}

}  // namespace

std::unique_ptr<RaceBots> RaceBots::make(const scenario::RaceSpec& race, const Model& m,
                                         const std::vector<int>& road_car) {
  if (race.bots <= 0) return nullptr;
  std::unique_ptr<RaceBots> b(new RaceBots());
  b->skill_ = race.bot_skill;
  std::shared_ptr<const drivers::Policy> policy;
  std::shared_ptr<const drivers::TrackCourse> course;
  if (!race.bot_policy.empty()) {
    policy = loadPolicy(race);
    course = std::make_shared<const drivers::TrackCourse>(race);
    b->period_ = std::max<std::int64_t>(1, std::llround(policy->controlPeriod() * policy->dt() / m.opt.dt));
  } else {
    b->line_ = std::make_unique<drivers::TrackLine>(drivers::racingLine(race), race.circuit, 1.0);
    b->profile_ = std::make_unique<drivers::SpeedProfile>(*b->line_, drivers::CarLimits{},
                                                          drivers::frictionAlong(m, *b->line_));
    b->period_ = std::max<std::int64_t>(1, std::llround(kControlPeriod / m.opt.dt));
  }
  const int n = static_cast<int>(road_car.size());
  for (int v = std::max(0, n - race.bots); v < n; ++v) {
    const int rc = road_car[static_cast<size_t>(v)];
    if (rc < 0) continue;
    Bot bot;
    bot.vehicle = v;
    bot.body = m.road_cars[static_cast<size_t>(rc)].body;
    const int body = m.road_cars[static_cast<size_t>(rc)].body;
    std::unique_ptr<drivers::Driver> driver;
    try {
      if (policy) driver = std::make_unique<drivers::PolicyDriver>(policy, course, body, race.bot_skill);
      else driver = std::make_unique<drivers::ClassicalBot>(*b->line_, *b->profile_, m, rc);
    } catch (const drivers::PolicyError& e) {
      throw scenario::ScenarioError({scenario::Issue{"/race/bot_policy", e.what()}});
    }
    // every other road car, players' and bots', in vehicle order: the traffic rules' order of way
    std::vector<int> others;
    int rank = 0;
    for (int o = 0; o < n; ++o) {
      const int orc = road_car[static_cast<size_t>(o)];
      if (o == v || orc < 0) continue;
      if (o < v) ++rank;
      others.push_back(m.road_cars[static_cast<size_t>(orc)].body);
      bot.others.push_back(o);
    }
    auto traffic = std::make_unique<drivers::TrafficAware>(std::move(driver), body, std::move(others), rank);
    bot.traffic = traffic.get();
    bot.driver = std::move(traffic);
    b->bots_.push_back(std::move(bot));
  }
  if (b->bots_.empty()) return nullptr;
  b->lost_.reserve(b->bots_.size());  // no allocation in the step loop
  return b;
}

const std::vector<RaceBots::Command>& RaceBots::drive(const Model& m, const State& s, const race::Race& race) {
  commands_.resize(bots_.size());  // sized once: no allocation in the step loop
  lost_.clear();
  const bool held = race.held(s.t);
  const double dt = static_cast<double>(period_) * m.opt.dt;
  drivers::Pedals hold;
  hold.brake = 1.0;
  for (size_t k = 0; k < bots_.size(); ++k) {
    Bot& bot = bots_[k];
    for (size_t o = 0; o < bot.others.size(); ++o) bot.traffic->setProtected(o, race.isProtected(bot.others[o], s.t));
    bot.traffic->setGhost(race.isProtected(bot.vehicle, s.t) && m.collisions);
    const drivers::Pedals p = held ? hold : bot.driver->drive(m, s);
    Command& c = commands_[k];
    c.vehicle = bot.vehicle;
    c.controls = drivers::toControls(p);
    c.controls.throttle = std::min(p.throttle, skill_);  // the skill caps the throttle
    if (!held) judge(bot, s, race, dt);
  }
  return commands_;
}

// Whether bot's car wants a respawn (lost_), as a player would see it.
void RaceBots::judge(Bot& bot, const State& s, const race::Race& race, double dt) {
  const race::CarStanding& st = race.standing(bot.vehicle);
  if (st.finished || race.isProtected(bot.vehicle, s.t)) {
    bot.stuck = bot.flipped = bot.astray = 0.0;
    return;
  }
  const Mat3 R = bodyRot(s.y, bot.body).normalized().toRotationMatrix();
  const double speed = Vec3(bodyVel(s.y, bot.body)).norm();
  bot.stuck = speed < kStuckSpeed ? bot.stuck + dt : 0.0;
  bot.flipped = R(2, 2) < 0.3 ? bot.flipped + dt : 0.0;  // its up axis more than ~73 degrees from the vertical
  bot.astray = st.off_track || st.wrong_way ? bot.astray + dt : 0.0;
  const double since_gate = s.t - std::max({st.last_cross, race.goTime(), bot.placed});
  if (bot.stuck >= kStuckFor || bot.flipped >= kFlippedFor || bot.astray >= kLostFor || since_gate >= kNoGateFor) {
    lost_.push_back(bot.vehicle);
    bot.stuck = bot.flipped = bot.astray = 0.0;
  }
}

void RaceBots::relocate(int vehicle, double t) {
  for (Bot& bot : bots_)
    if (bot.vehicle == vehicle) bot.restart(t);
}

void RaceBots::relocateAll(double t) {
  for (Bot& bot : bots_) bot.restart(t);
}

bool RaceBots::drives(int vehicle) const {
  return std::any_of(bots_.begin(), bots_.end(), [vehicle](const Bot& b) { return b.vehicle == vehicle; });
}

}  // namespace groundsim::session
