// Traffic rules for computer drivers (docs/drivers.md, "Traffic"): any
// driver's pedals, kept off the cars ahead. Neither the classical driver
// nor a policy trained alone sees other cars; this layer does, as the
// collision avoidance of TORCS robots does: a car ahead in the bot's path
// (a corridor about its heading) closer than a time headway caps the
// throttle, and closer than the distance the closing speed needs to shed
// brakes. Other cars are read from the simulation's state, so a race with
// bots still re-simulates from its applied log alone.
#pragma once

#include <memory>
#include <vector>

#include "drivers/driver.hpp"

namespace groundsim::drivers {

struct TrafficRules {
  double corridor = 2.2;    // m    half width of the path watched (a car's width plus a margin each side)
  double beside = 3.6;      // m    and of the path within `near` of its nose: a car alongside that merges
  double near = 8.0;        // m
  double lane = 5.5;        // m    a car overlapping this one within this, side to side: not steered towards
  bool steer_clear = true;  //      whether that steering rule applies
  double look = 40.0;       // m    how far ahead
  double length = 4.8;      // m    centre to centre, bumpers touching (a sedan's length)
  double min_gap = 2.0;     // m    bumper to bumper, kept at standstill
  double headway = 0.6;     // s    gap kept per m/s of the bot's own speed
  double decel = 6.0;       // m/s^2  braking assumed to shed a closing speed
};

class TrafficAware : public Driver {
 public:
  // `inner` drives the car of body `body`; `others`: the other cars'
  // bodies. Cars side by side (neither a metre ahead) that merge: the one
  // later in `others`' order than this one yields, so that of two such
  // bots exactly one does (`rank`: this car's place in that order).
  TrafficAware(std::unique_ptr<Driver> inner, int body, std::vector<int> others, int rank, TrafficRules rules = {});
  Pedals drive(const Model& m, const State& s) override;
  void relocate() override { inner_->relocate(); }
  // Whether the last call changed the inner driver's pedals.
  bool yielded() const { return yielded_; }

 private:
  std::unique_ptr<Driver> inner_;
  int body_ = 0;
  std::vector<int> others_;
  int rank_ = 0;
  TrafficRules rules_;
  bool yielded_ = false;
};

}  // namespace groundsim::drivers
