// The keys of a `"kind": "road_car"` vehicle (physics/road_car/road_car.hpp holds
// their meaning, units and defaults; docs/vehicles.md lists them) and its
// `controls` time table.
#include <cmath>
#include <numbers>

#include "scenario/sections.hpp"

namespace groundsim::scenario {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

void readSuspension(ObjectReader r, SuspensionParams& s) {
  const SuspensionParams d = s;
  s.ride_frequency = r.number("ride_frequency", d.ride_frequency, Range::positive(20.0));
  s.damping_ratio = r.number("damping_ratio", d.damping_ratio, Range::nonNegative(5.0));
  s.bump_travel = r.number("bump_travel", d.bump_travel, Range::nonNegative(2.0));
  s.droop_travel = r.number("droop_travel", d.droop_travel, Range::nonNegative(2.0));
  s.stop_stiffness = r.number("stop_stiffness", d.stop_stiffness, Range::nonNegative());
  s.anti_roll = r.number("anti_roll", d.anti_roll, Range::nonNegative());
  r.finish();
}

void readTyre(ObjectReader r, TyreParams& t) {
  const TyreParams d = t;
  t.slip_model = r.choice("model", d.slip_model ? "magic_formula" : "stick_slip", {"magic_formula", "stick_slip"}) == "magic_formula";
  t.vertical_stiffness = r.number("vertical_stiffness", d.vertical_stiffness, Range::positive());
  t.vertical_damping = r.number("vertical_damping", d.vertical_damping, Range::nonNegative());
  t.nominal_load = r.number("nominal_load", d.nominal_load, Range::nonNegative());
  t.cornering_stiffness = r.number("cornering_stiffness", d.cornering_stiffness, Range::positive());
  t.longitudinal_stiffness = r.number("longitudinal_stiffness", d.longitudinal_stiffness, Range::positive());
  t.load_sensitivity = r.number("load_sensitivity", d.load_sensitivity, Range::closed(0.0, 0.5));
  t.friction_scale = r.number("friction_scale", d.friction_scale, Range::positive(10.0));
  t.sliding_ratio = r.number("sliding_ratio", d.sliding_ratio, Range::closed(0.05, 0.99));
  t.peak_slip_ratio = r.number("peak_slip_ratio", d.peak_slip_ratio, Range::closed(0.01, 0.5));
  t.peak_slip_angle = r.number("peak_slip_angle_deg", d.peak_slip_angle / kDeg, Range::closed(0.5, 30.0)) * kDeg;
  t.relaxation_length = r.number("relaxation_length", d.relaxation_length, Range::closed(0.01, 5.0));
  t.low_speed_damping = r.number("low_speed_damping", d.low_speed_damping, Range::nonNegative());
  t.rolling_resistance = r.number("rolling_resistance", d.rolling_resistance, Range::nonNegative(0.5));
  r.finish();
}

// "front" and "rear" objects, or the keys directly for both axles.
template <class T, class F>
void readAxles(ObjectReader r, std::array<T, 2>& axles, F read) {
  if (r.has("front") || r.has("rear")) {
    read(r.object("front"), axles[0]);
    read(r.object("rear"), axles[1]);
    r.finish();
  } else {
    read(r, axles[0]);
    axles[1] = axles[0];
  }
}

void readPowertrain(ObjectReader r, PowertrainParams& p) {
  const PowertrainParams d = p;
  p.present = r.boolean("present", d.present);
  const std::string kind = r.choice("engine", "combustion", {"combustion", "electric"});
  p.electric = kind == "electric";
  p.rpm = r.numbers("torque_rpm", d.rpm, Range::positive(1e5), 2, 64);
  p.torque = r.numbers("torque", d.torque, Range::nonNegative(1e5), 2, 64);
  if (p.rpm.size() != p.torque.size())
    r.issue("torque", "needs one value per torque_rpm entry (" + std::to_string(p.rpm.size()) + "), got " +
                          std::to_string(p.torque.size()));
  for (size_t i = 1; i < p.rpm.size(); ++i)
    if (!(p.rpm[i] > p.rpm[i - 1])) {
      r.issue("torque_rpm", "must increase, entry " + std::to_string(i) + " does not");
      break;
    }
  p.idle_rpm = r.number("idle_rpm", d.idle_rpm, Range::positive(1e5));
  p.redline_rpm = r.number("redline_rpm", d.redline_rpm, Range::positive(1e5));
  if (!(p.redline_rpm > p.idle_rpm))
    r.issue("redline_rpm", "must exceed idle_rpm (" + formatNumber(p.idle_rpm) + ")");
  p.launch_rpm = r.number("launch_rpm", d.launch_rpm, Range::positive(1e5));
  p.engine_braking = r.number("engine_braking", d.engine_braking, Range::nonNegative(1e5));
  p.motor_torque = r.number("motor_torque", d.motor_torque, Range::positive(1e6));
  p.motor_power = r.number("motor_power", d.motor_power, Range::positive(1e8));
  p.motor_max_rpm = r.number("motor_max_rpm", d.motor_max_rpm, Range::positive(1e6));
  p.gears = r.numbers("gears", d.gears, Range::positive(100.0), 1, 16);
  p.reverse_gear = r.number("reverse_gear", d.reverse_gear, Range::positive(100.0));
  p.final_drive = r.number("final_drive", d.final_drive, Range::positive(100.0));
  p.efficiency = r.number("efficiency", d.efficiency, Range{0.0, 1.0, true, false});
  const std::string drive = r.choice("drive", "rear", {"rear", "front", "all"});
  p.drive = drive == "front" ? Drive::Front : drive == "all" ? Drive::All : Drive::Rear;
  p.front_share = r.number("front_share", d.front_share, Range::closed(0.0, 1.0));
  p.shift_interval = r.number("shift_interval", d.shift_interval, Range::nonNegative(60.0));
  r.finish();
}

void readBrakes(ObjectReader r, BrakeParams& b) {
  const BrakeParams d = b;
  b.max_torque = r.number("max_torque", d.max_torque, Range::nonNegative(1e6));
  b.front_share = r.number("front_share", d.front_share, Range::closed(0.0, 1.0));
  b.handbrake_torque = r.number("handbrake_torque", d.handbrake_torque, Range::nonNegative(1e6));
  b.abs = r.boolean("abs", d.abs);
  b.traction_control = r.boolean("traction_control", d.traction_control);
  b.abs_min_speed = r.number("abs_min_speed", d.abs_min_speed, Range::nonNegative(100.0));
  r.finish();
}

void readSteering(ObjectReader r, SteeringParams& s) {
  const SteeringParams d = s;
  s.max_angle = r.number("max_angle_deg", d.max_angle / kDeg, Range::closed(0.0, 60.0)) * kDeg;
  s.rate = r.number("rate_deg", d.rate / kDeg, Range::positive(1e4)) * kDeg;
  s.ackermann = r.number("ackermann", d.ackermann, Range::closed(0.0, 1.0));
  r.finish();
}

void readAero(ObjectReader r, AeroParams& a) {
  const AeroParams d = a;
  a.drag_area = r.number("drag_area", d.drag_area, Range::nonNegative(100.0));
  a.air_density = r.number("air_density", d.air_density, Range::nonNegative(100.0));
  r.finish();
}

}  // namespace

void readRoadCar(ObjectReader& r, RoadCarParams& p) {
  const RoadCarParams d;
  p.mass = r.number("mass", d.mass, Range::positive(1e6));
  p.inertia = r.vec3("inertia", d.inertia, Range::positive(1e8));
  p.wheelbase = r.number("wheelbase", d.wheelbase, Range::positive(100.0));
  p.cg_to_front = r.number("cg_to_front", d.cg_to_front, Range::positive(100.0));
  if (!(p.cg_to_front < p.wheelbase))
    r.issue("cg_to_front", "must be < wheelbase (" + formatNumber(p.wheelbase) + "), got " + formatNumber(p.cg_to_front));
  p.cg_height = r.number("cg_height", d.cg_height, Range::positive(100.0));
  p.track = r.number("track", d.track, Range::positive(100.0));
  p.wheel_radius = r.number("wheel_radius", d.wheel_radius, Range::positive(10.0));
  p.wheel_mass = r.number("wheel_mass", d.wheel_mass, Range::positive(1e5));
  p.wheel_inertia = r.number("wheel_inertia", d.wheel_inertia, Range::positive(1e5));
  // 0 entries: derived from wheelbase, track and cg_height (road_car.hpp)
  p.body_size = r.vec3("body_size", d.body_size, Range::nonNegative(100.0));
  if (!(p.mass > 4.0 * p.wheel_mass))
    r.issue("wheel_mass", "four wheels must weigh less than the car (" + formatNumber(p.mass) + " kg)");
  readAxles(r.object("suspension"), p.suspension, readSuspension);
  readAxles(r.object("tyres"), p.tyre, readTyre);
  readPowertrain(r.object("powertrain"), p.powertrain);
  readBrakes(r.object("brakes"), p.brakes);
  readSteering(r.object("steering"), p.steering);
  readAero(r.object("aero"), p.aero);
}

std::vector<TimedControls> readControlTable(ObjectReader& r, int gears) {
  std::vector<TimedControls> out;
  CarControls held;
  double last_t = -1.0;
  for (ObjectReader e : r.objects("controls")) {
    TimedControls tc;
    const auto t = e.requiredNumber("t", Range::nonNegative(1e6));
    tc.t = t.value_or(last_t < 0 ? 0.0 : last_t);
    if (t && *t < last_t)
      e.issue("t", "must not be earlier than the previous entry's (" + formatNumber(last_t) + "), got " + formatNumber(*t));
    last_t = std::max(last_t, tc.t);
    // each entry sets the fields it names; the rest hold from the entry before
    if (e.has("throttle")) held.throttle = e.number("throttle", 0.0, Range::closed(0.0, 1.0));
    else e.allow("throttle");
    if (e.has("brake")) held.brake = e.number("brake", 0.0, Range::closed(0.0, 1.0));
    else e.allow("brake");
    if (e.has("steer")) held.steer = e.number("steer", 0.0, Range::closed(-1.0, 1.0));
    else e.allow("steer");
    if (e.has("handbrake")) held.handbrake = e.boolean("handbrake", false);
    else e.allow("handbrake");
    if (e.has("gear")) {
      std::vector<std::string> names{"auto", "R", "N"};
      for (int g = 1; g <= gears; ++g) names.push_back(std::to_string(g));
      const std::string g = e.choice("gear", "auto", names);
      held.gear = g == "auto" ? CarControls::kAuto : g == "R" ? CarControls::kReverse
                  : g == "N" ? CarControls::kNeutral : std::stoi(g);
    } else {
      e.allow("gear");
    }
    if (e.has("wheel_torque")) {
      const Eigen::VectorXd w = e.vector("wheel_torque", Eigen::VectorXd::Zero(4), Range::closed(-1e5, 1e5));
      for (int k = 0; k < 4; ++k) held.wheel_torque[static_cast<size_t>(k)] = w[k];
    } else {
      e.allow("wheel_torque");
    }
    e.finish();
    tc.controls = held;
    out.push_back(tc);
  }
  return out;
}

}  // namespace groundsim::scenario
