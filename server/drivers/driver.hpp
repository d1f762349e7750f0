// A computer driver at the wheel of one road car, as a session gives it
// the wheel (session/race_bots.hpp): it senses the car in the simulation's
// state and answers with pedals. Two kinds: the classical baseline
// (ClassicalBot) and a trained policy (PolicyDriver).
#pragma once

#include "drivers/classical_driver.hpp"
#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/road_car/road_car.hpp"

namespace groundsim::drivers {

// The road car's controls of a driver's pedals (automatic gears, or reverse).
inline CarControls toControls(const Pedals& p) {
  CarControls c;
  c.throttle = p.throttle;
  c.brake = p.brake;
  c.steer = p.steer;
  c.gear = p.reverse ? CarControls::kReverse : CarControls::kAuto;
  return c;
}

class Driver {
 public:
  virtual ~Driver() = default;
  virtual Pedals drive(const Model& m, const State& s) = 0;
  // The car was put elsewhere (a respawn, a reset): find it again.
  virtual void relocate() = 0;
};

}  // namespace groundsim::drivers
