// The report's car (section 3): a body of 8 axle points and four wheels of
// n rim points, each rim point tied by a spring-dashpot to both axle points
// of its corner. Defaults are the report code's values (shared/physics-notes).
// Alternatives for the speed/accuracy trade: a continuous wheel (contact of
// the exact circle) and a bearing coupling (two zero-length springs along
// the axle instead of 2n rim springs).
#pragma once

#include <array>
#include <string>

#include "physics/build/model_builder.hpp"

namespace groundsim {

enum class WheelCoupling { RimSprings, Bearing };

// The front wheels' angle at full lock: the vehicle's default max_steer, and
// what a full turn of every control path asks for (groundsim drive, the
// bridge's ControlScale, the page's predictor; the page's JavaScript gets
// it from this line at bundle time: web/CMakeLists.txt, GROUNDSIM_FULL_LOCK).
inline constexpr double kFullLockRad = 0.6;  // rad

struct CarParams {
  int rim_points = 20;              // -      points per wheel rim
  double wheel_radius = 1.0;        // m
  double half_length = 1.5;         // m      body centre to front / rear axle
  double half_width = 1.0;          // m      body centre to each wheel plane
  double axle_half_length = 0.25;   // m      wheel centre to each of its axle points
  double body_mass = 1.0;           // kg     spread over the 8 axle points
  double wheel_mass = 0.1;          // kg     per wheel, spread over its rim
  double rim_stiffness = 1e5;       // N/m    per rim spring
  double rim_damping = 2.0;         // N s/m  per rim spring
  WheelContact wheel_contact = WheelContact::RimPoints;
  WheelCoupling coupling = WheelCoupling::RimSprings;
  double bearing_stiffness = 1e5;   // N/m    per bearing spring
  double bearing_damping = 20.0;    // N s/m  per bearing spring
  double max_steer = kFullLockRad;  // rad    front wheels
  double steer_rate = 1.0;          // rad/s  fastest steering change
  bool body_contact = true;         // -      axle points touch the ground too (rollover)
  // Deformable tyre: the rim is a ring of free point masses, laced to a
  // rigid hub by crossed spokes (so they carry drive and brake torque) and
  // tied to its neighbours by tread springs; the hub turns on the bearing.
  bool deformable = false;
  double tyre_stiffness = 2e3;      // N/m    per spoke (4 per rim point)
  double tyre_damping = 2.0;        // N s/m  per spoke
  double tread_stiffness = 2e3;     // N/m    between rim neighbours (and next-but-one)
  double hub_mass_fraction = 0.3;   // -      of wheel_mass in the hub, the rest in the rim
};

struct CarPlacement {
  Vec3 position = Vec3::Zero();     // m      body centre; with on_ground only x and y count
  double yaw = 0.0;                 // rad    heading about the vertical (0: +x)
  double roll = 0.0, pitch = 0.0;   // rad    without on_ground only
  bool on_ground = true;            // -      align with the ground normal, wheels touching
  double clearance = 0.0;           // m      gap below the lowest wheel when on_ground
  double speed = 0.0;               // m/s    initial forward velocity
  double wheel_spin = 0.0;          // rad/s  initial spin of every wheel about its axle
};

struct CarHandle {
  int vehicle = -1;
  int body = -1;
  std::array<int, 4> wheels{};      // front-left, front-right, rear-left, rear-right
};

CarHandle addCar(ModelBuilder& b, const std::string& name, const CarParams& p, const CarPlacement& at);

// A lone wheel (a hoop of rim_points, wheel_mass, wheel_radius; rim-point or
// circle contact) standing upright, its axle along the placement's left.
// It is its own vehicle body; its drive torque is external (no carrier).
CarHandle addLoneWheel(ModelBuilder& b, const std::string& name, const CarParams& p, const CarPlacement& at);

// groundPointBelow: see ground.hpp.

}  // namespace groundsim
