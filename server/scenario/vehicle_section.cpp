#include <cmath>
#include <numbers>

#include "scenario/sections.hpp"

namespace groundsim::scenario {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Names appear in CSV columns, telemetry and LCM channel names: keep them
// to characters that need no quoting anywhere.
bool validName(const std::string& s) {
  if (s.empty() || s.size() > 32) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

void readParams(ObjectReader& r, CarParams& p) {
  const CarParams def;
  // 3 points make the smallest rim polygon; 10000 per wheel is far beyond
  // any useful resolution (physics-notes: 160 points already costs 8x)
  p.rim_points = r.integer("rim_points", def.rim_points, 3, 10000);
  p.wheel_radius = r.number("wheel_radius", def.wheel_radius, Range::positive(100.0));
  p.half_length = r.number("half_length", def.half_length, Range::positive(1e3));
  p.half_width = r.number("half_width", def.half_width, Range::positive(1e3));
  p.axle_half_length = r.number("axle_half_length", def.axle_half_length, Range::positive(1e3));
  p.body_mass = r.number("body_mass", def.body_mass, Range::positive(1e6));
  p.wheel_mass = r.number("wheel_mass", def.wheel_mass, Range::positive(1e6));
  p.rim_stiffness = r.number("rim_stiffness", def.rim_stiffness, Range::positive());
  p.rim_damping = r.number("rim_damping", def.rim_damping, Range::nonNegative());
  const std::string model = r.choice("wheel_model", "rim_points", {"rim_points", "circle", "deformable"});
  p.wheel_contact = model == "circle" ? WheelContact::Circle : WheelContact::RimPoints;
  p.deformable = model == "deformable";
  p.tyre_stiffness = r.number("tyre_stiffness", def.tyre_stiffness, Range::positive());
  p.tyre_damping = r.number("tyre_damping", def.tyre_damping, Range::nonNegative());
  p.tread_stiffness = r.number("tread_stiffness", def.tread_stiffness, Range::positive());
  p.hub_mass_fraction = r.number("hub_mass_fraction", def.hub_mass_fraction, Range::closed(0.05, 0.95));
  p.coupling = r.choice("coupling", "rim_springs", {"rim_springs", "bearing"}) == "bearing"
                   ? WheelCoupling::Bearing
                   : WheelCoupling::RimSprings;
  p.bearing_stiffness = r.number("bearing_stiffness", def.bearing_stiffness, Range::positive());
  p.bearing_damping = r.number("bearing_damping", def.bearing_damping, Range::nonNegative());
  p.max_steer = r.number("max_steer_deg", def.max_steer / kDeg, Range::closed(0.0, 89.0)) * kDeg;
  p.body_contact = r.boolean("body_contact", def.body_contact);
}

void readInitial(ObjectReader r, CarPlacement& at) {
  const CarPlacement def;
  at.position = r.vec3("position", def.position);
  at.yaw = r.number("yaw_deg", def.yaw / kDeg, Range::closed(-360.0, 360.0)) * kDeg;
  at.roll = r.number("roll_deg", def.roll / kDeg, Range::closed(-180.0, 180.0)) * kDeg;
  at.pitch = r.number("pitch_deg", def.pitch / kDeg, Range::closed(-90.0, 90.0)) * kDeg;
  at.on_ground = r.boolean("on_ground", def.on_ground);
  at.clearance = r.number("clearance", def.clearance, Range::nonNegative(1e3));
  at.speed = r.number("speed", def.speed, Range::closed(-1e3, 1e3));
  at.wheel_spin = r.number("wheel_spin", def.wheel_spin, Range::closed(-1e4, 1e4));
  r.finish();
}

void readControl(ObjectReader r, VehicleControlSpec& c, double max_steer) {
  c.drive_torque = r.number("drive_torque", 0.0);
  const std::string wheels = r.choice("drive_wheels", "all", {"all", "front", "rear"});
  c.drive_wheels = wheels == "front" ? DriveWheels::Front : wheels == "rear" ? DriveWheels::Rear : DriveWheels::All;
  c.brake_torque = r.number("brake_torque", 0.0, Range::nonNegative());
  const double steer_deg = r.number("steer_deg", 0.0, Range::closed(-89.0, 89.0));
  if (std::abs(steer_deg * kDeg) > max_steer + 1e-12)
    r.issue("steer_deg", "must be within max_steer_deg (" + formatNumber(max_steer / kDeg) + "), got " +
                             formatNumber(steer_deg));
  else
    c.steer = steer_deg * kDeg;
  r.finish();
}

}  // namespace

VehicleSpec readVehicle(ObjectReader r) {
  VehicleSpec v;
  v.name = r.string("name", v.name);
  if (!validName(v.name))
    r.issue("name", "must be 1-32 letters, digits, '_' or '-', got " + quote(v.name));
  const std::string kind = r.choice("kind", "car", {"car", "wheel", "road_car"});
  v.lone_wheel = kind == "wheel";
  v.road_car = kind == "road_car";
  if (v.road_car) {
    readRoadCar(r, v.road);
    readInitial(r.object("initial"), v.placement);
    v.controls = readControlTable(r, static_cast<int>(v.road.powertrain.gears.size()));
    r.finish();
    return v;
  }
  readParams(r, v.params);
  if (v.lone_wheel && v.params.deformable)
    r.issue("wheel_model", "a lone wheel is \"rim_points\" or \"circle\"; \"deformable\" needs a car");
  // the inner axle point of a wheel must stay on its own side of the body
  if (v.params.axle_half_length >= v.params.half_width)
    r.issue("axle_half_length", "must be < half_width (" + formatNumber(v.params.half_width) + "), got " +
                                    formatNumber(v.params.axle_half_length));
  readInitial(r.object("initial"), v.placement);
  readControl(r.object("control"), v.control, v.params.max_steer);
  r.finish();
  return v;
}

}  // namespace groundsim::scenario
