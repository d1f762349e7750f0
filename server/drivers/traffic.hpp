// Traffic rules for computer drivers (docs/drivers.md, "Traffic"): any
// driver's pedals, kept off the cars ahead. Neither the classical driver
// nor a policy trained alone sees other cars; this layer does, as the
// collision avoidance of TORCS robots does: a car ahead in the bot's path
// (a corridor about its heading) closer than a time headway caps the
// throttle, and closer than the distance the closing speed needs to shed
// brakes; a car stopped in its path for 2 s (an idle player on the grid, a
// crashed car) it goes round, backing off first when too close to turn
// out. A car under respawn protection has the way: the bot gives it room
// across its whole lane, lets it go first when alongside, and never goes
// round it (it is about to drive off). Other cars are read from the
// simulation's state (and the race's protections), so a race with bots
// still re-simulates from its applied log alone.
#pragma once

#include <cstddef>
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
  // Car k of `others` (its index there) is under respawn protection, or
  // no longer (race.respawn_protection; the session sets it before each
  // drive): it has the way.
  void setProtected(std::size_t k, bool on) { protected_.at(k) = on ? 1 : 0; }
  // This bot's own car is under respawn protection: it passes through the
  // others, so it keeps no rule and drives as its inner driver does.
  void setGhost(bool on) { ghost_ = on; }
  void relocate() override {
    inner_->relocate();
    last_t_ = -1.0, blocked_ = 0.0, passing_ = -1;
  }
  // Whether the last call changed the inner driver's pedals.
  bool yielded() const { return yielded_; }
  // Whether it is going round a car stopped in its path.
  bool passing() const { return passing_ >= 0; }

 private:
  struct Ahead {
    int index = -1;           // in others_: the nearest car in the path, -1: none
    double gap = 1e300;       // m   bumper to bumper
    double closing = 0.0;     // m/s
    double their_speed = 0.0; // m/s
    bool merging = false;     // a car alongside and ahead of it merges
  };
  Ahead look(const State& s, const Mat3& R, const Vec3& c, const Vec3& fwd, double speed, Pedals& p);
  void passIfBlocked(const State& s, const Mat3& R, const Vec3& c, const Ahead& ahead, double dt, Pedals& p);
  void keepGap(const Ahead& ahead, double speed, Pedals& p);
  bool carBehind(const State& s, const Mat3& R, const Vec3& c) const;

  std::unique_ptr<Driver> inner_;
  int body_ = 0;
  std::vector<int> others_;
  std::vector<char> protected_;  // per car of others_: under respawn protection
  int rank_ = 0;
  TrafficRules rules_;
  bool yielded_ = false;
  bool ghost_ = false;
  double last_t_ = -1.0;     // s   the state's time at the last call
  double blocked_ = 0.0;     // s   behind a stopped car so far
  int passing_ = -1;         // the car it goes round (in others_), -1: none
  double side_ = 1.0;        // +1 round it on the left, -1 on the right
  bool backing_ = false;     // backing off from it first
};

}  // namespace groundsim::drivers
