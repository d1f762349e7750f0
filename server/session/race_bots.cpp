#include "session/race_bots.hpp"

#include <algorithm>
#include <cmath>

#include "drivers/lap_run.hpp"

namespace groundsim::session {

RaceBots::RaceBots(const scenario::RaceSpec& race, const Model& m)
    : line_(drivers::racingLine(race), race.circuit, 1.0),
      profile_(line_, drivers::CarLimits{}, drivers::frictionAlong(m, line_)),
      period_(std::max<std::int64_t>(1, std::llround(kControlPeriod / m.opt.dt))) {}

std::unique_ptr<RaceBots> RaceBots::make(const scenario::RaceSpec& race, const Model& m,
                                         const std::vector<int>& road_car) {
  if (race.bots <= 0) return nullptr;
  std::unique_ptr<RaceBots> b(new RaceBots(race, m));
  const int n = static_cast<int>(road_car.size());
  for (int v = std::max(0, n - race.bots); v < n; ++v) {
    if (road_car[static_cast<size_t>(v)] < 0) continue;
    Bot bot;
    bot.vehicle = v;
    bot.road_car = road_car[static_cast<size_t>(v)];
    bot.driver = std::make_unique<drivers::ClassicalDriver>(b->line_, b->profile_,
                                                            drivers::carGeometry(m, bot.road_car));
    b->bots_.push_back(std::move(bot));
  }
  if (b->bots_.empty()) return nullptr;
  return b;
}

const std::vector<RaceBots::Command>& RaceBots::drive(const Model& m, const State& s) {
  commands_.resize(bots_.size());  // sized once: no allocation in the step loop
  for (size_t k = 0; k < bots_.size(); ++k) {
    const drivers::Pedals p = bots_[k].driver->drive(drivers::senseCar(m, s, bots_[k].road_car));
    Command& c = commands_[k];
    c.vehicle = bots_[k].vehicle;
    c.controls = CarControls{};
    c.controls.throttle = p.throttle;
    c.controls.brake = p.brake;
    c.controls.steer = p.steer;
  }
  return commands_;
}

void RaceBots::relocate(int vehicle) {
  for (Bot& bot : bots_)
    if (bot.vehicle == vehicle) bot.driver->relocate();
}

void RaceBots::relocateAll() {
  for (Bot& bot : bots_) bot.driver->relocate();
}

bool RaceBots::drives(int vehicle) const {
  return std::any_of(bots_.begin(), bots_.end(), [vehicle](const Bot& b) { return b.vehicle == vehicle; });
}

}  // namespace groundsim::session
