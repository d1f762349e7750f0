// A road car (issue 9): one rigid body (the whole car's mass and inertia)
// with four wheels, each on its own carrier guided along the body's strut
// axis (a 1-DOF prismatic joint solved analytically, see suspension.cpp),
// a slip-based tyre with deflection states (tyre.cpp), a powertrain with
// engine or motor, gearbox and open differentials (powertrain.cpp), brakes
// with ABS and traction control, Ackermann steering (steering.cpp) and
// aerodynamic drag. Every part is optional: a car without a powertrain
// rolls, one without suspension has stiff springs... (see docs/vehicles.md).
//
// Its continuous states sit after the bodies and particles in State::y,
// five per wheel: travel s (m, + = compression), its rate (m/s), spin
// omega (rad/s, + = forward), tyre deflections u_x, u_y (m).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "physics/base/math.hpp"

namespace groundsim {

// Pacejka Magic Formula, combined slip by normalised slip (Pacejka 2006,
// 4.3.2), with its shape fitted from physical figures at load; or the rigid
// stick-slip contact.
struct TyreParams {
  // true: the Magic Formula below; false (`tyres.model: "stick_slip"`): the
  // rigid stick-slip contact (tyre_stick_slip.cpp), which reads only the
  // vertical figures, friction_scale, sliding_ratio and rolling_resistance
  bool slip_model = true;
  double vertical_stiffness = 2e5;  // N/m
  double vertical_damping = 500.0;  // N s/m
  double nominal_load = 0.0;        // N      F_z0; 0: the static load of the tyre's corner
  double cornering_stiffness = 6e4; // N/rad  C_alpha at the nominal load
  double longitudinal_stiffness = 8e4;  // N  C_kappa (per unit slip) at the nominal load
  double load_sensitivity = 0.1;    // -      stiffness C(F_z) = C0 z (1 - e (z - 1)), z = F_z / F_z0
  double friction_scale = 1.0;      // -      peak friction = ground friction * this
  double sliding_ratio = 0.8;       // -      sliding friction / peak friction (sets the MF shape factor C)
  double peak_slip_ratio = 0.12;    // -      kappa at the longitudinal peak
  double peak_slip_angle = 0.12;    // rad    alpha at the lateral peak (~7 deg)
  double relaxation_length = 0.3;   // m      sigma: deflection builds over this rolled distance
  double low_speed_damping = 3e3;   // N s/m  on the deflection rate, faded out by 3 m/s
  double rolling_resistance = 0.012;// -      C_rr
  // derived from sliding_ratio when built (tyre.cpp), 0 = compute per call
  double shape_c = 0.0, shape_tan = 0.0;
  // reciprocals of relaxation_length, peak_slip_ratio and peak_slip_angle,
  // set by addRoadCar so an evaluation multiplies (the road car's step reads
  // them as set); 0: deflectionRates divides and tyreForces4 takes
  // tyreForces lane by lane (a TyreParams used outside a built car)
  double inv_relaxation = 0.0, inv_peak_slip_ratio = 0.0, inv_peak_slip_angle = 0.0;
};

struct SuspensionParams {
  double ride_frequency = 1.3;      // Hz     corner ride frequency (spring in series with the tyre)
  double damping_ratio = 0.3;       // -      of that corner mode
  double bump_travel = 0.08;        // m      compression before the bump stop
  double droop_travel = 0.10;       // m      extension before the droop stop
  double stop_stiffness = 1.5e5;    // N/m    bump/droop stop beyond the travel
  double anti_roll = 0.0;           // N/m    anti-roll bar rate (per unit travel difference)
};

enum class Drive { Rear, Front, All };

struct PowertrainParams {
  bool present = true;
  bool electric = false;
  // combustion engine: torque table over rpm (full throttle), linear between
  std::vector<double> rpm{1000, 2000, 3000, 4000, 5000, 5500, 6000, 6500};
  std::vector<double> torque{140, 190, 210, 215, 205, 191, 170, 150};  // N m
  double idle_rpm = 900.0;          // rpm
  double redline_rpm = 6500.0;      // rpm    fuel cut above
  double launch_rpm = 2500.0;       // rpm    engine speed while the clutch slips at full throttle
  double engine_braking = 40.0;     // N m    drag torque at redline with the throttle shut (linear in rpm)
  // electric motor: constant torque up to the base speed, then constant power
  double motor_torque = 300.0;      // N m
  double motor_power = 110e3;       // W
  double motor_max_rpm = 12000.0;   // rpm
  std::vector<double> gears{3.6, 2.1, 1.4, 1.0, 0.8, 0.65};  // -  (an electric car: usually one)
  double reverse_gear = 3.4;        // -
  double final_drive = 3.9;         // -
  double efficiency = 0.9;          // -
  Drive drive = Drive::Rear;
  double front_share = 0.5;         // -      AWD torque to the front axle
  double shift_interval = 0.4;      // s      shortest time between automatic shifts
};

struct BrakeParams {
  double max_torque = 6000.0;       // N m    all four wheels together at brake 1
  double front_share = 0.7;         // -      brake balance
  double handbrake_torque = 2500.0; // N m    per rear wheel
  bool abs = true;
  bool traction_control = true;
  double abs_min_speed = 1.0;       // m/s    ABS and traction control hold the peak slip above this speed
};

struct SteeringParams {
  double max_angle = 35.0 * 3.14159265358979323846 / 180.0;  // rad  mean front road-wheel angle at steer 1
  double rate = 1.2;                // rad/s  fastest change of that angle
  double ackermann = 1.0;           // -      1: inner/outer angles meet on the rear axle line, 0: parallel
};

struct AeroParams {
  double drag_area = 0.66;          // m^2    C_d A
  double air_density = 1.225;       // kg/m^3
};

struct RoadCarParams {
  double mass = 1500.0;             // kg     whole car, wheels included
  Vec3 inertia{550.0, 2400.0, 2600.0};  // kg m^2 roll / pitch / yaw about the centre of mass
  double wheelbase = 2.70;          // m
  double cg_to_front = 1.20;        // m      centre of mass behind the front axle (a)
  double cg_height = 0.55;          // m      above the ground at design ride height
  double track = 1.55;              // m
  double wheel_radius = 0.32;       // m
  double wheel_mass = 20.0;         // kg     unsprung, per wheel
  double wheel_inertia = 1.0;       // kg m^2 spin
  // body box for contact with other bodies (build/collision_build.cpp),
  // length, width, height from the ground at design ride height; a zero
  // entry: 1.74 wheelbase, 1.16 track, 2.64 cg_height (a sedan's 4.7 x 1.8 x 1.45)
  Vec3 body_size = Vec3::Zero();    // m
  std::array<SuspensionParams, 2> suspension{};  // front, rear
  std::array<TyreParams, 2> tyre{};              // front, rear
  PowertrainParams powertrain;
  BrakeParams brakes;
  SteeringParams steering;
  AeroParams aero;
};

// What a driver or a policy commands, normalised.
struct CarControls {
  static constexpr int kAuto = 0, kReverse = -1, kNeutral = -2;
  double throttle = 0.0;            // [0, 1]
  double brake = 0.0;               // [0, 1]
  double steer = 0.0;               // [-1, 1]  + = left
  bool handbrake = false;
  int gear = kAuto;                 // kAuto, kReverse, kNeutral, or a manual gear 1..n
  std::array<double, 4> wheel_torque{};  // N m  extra drive torque per wheel (experiments)
};

// Per step: the discrete part of the car's state (in State, saved with it).
struct CarRuntime {
  CarControls applied;              // clamped controls
  double steer_angle = 0.0;         // rad    mean road-wheel angle, rate-limited
  int gear = 1;                     // engaged: 1..n, -1 reverse, 0 neutral
  double since_shift = 1e9;         // s
};

// Model part: derived at build.
struct RoadCar {
  int vehicle = -1;
  int body = -1;
  int aux = 0;                      // offset of its 20 states inside the aux block of y
  RoadCarParams p;
  std::array<Vec3, 4> hub;          // m      wheel centre at zero travel, body frame (FL, FR, RL, RR)
  std::array<double, 4> spring_rate{}, damper_rate{}, preload{}, static_load{};  // N/m, N s/m, N, N
  std::array<double, 4> nominal_load{};  // N  tyre F_z0
  std::array<double, 4> inv_nominal_load{};  // 1/N  its reciprocal
  // Inverse of the body's reduced mass matrix (reducedMassBody) in the body
  // frame, (linear, angular) order. It is constant there: the struts are the
  // body's z axis and a hub moves only along its strut, so r_hub x n has the
  // same body-frame components at every travel. Set by addRoadCar.
  Eigen::Matrix<double, 6, 6, Eigen::DontAlign> inv_mass_body =
      Eigen::Matrix<double, 6, 6, Eigen::DontAlign>::Zero();
};

// The body-frame reduced mass matrix of a road car whose body has this mass
// and body-frame inertia: diag(m, m, m, I) - m_u sum_w j_w j_w^T with
// j_w = (e_z, hub_w x e_z).
Eigen::Matrix<double, 6, 6> reducedMassBody(const RoadCar& rc, double mass, const Mat3& inertia);

// Per evaluation: what each wheel did (telemetry, tests).
struct RoadWheelOut {
  double normal = 0.0;              // N
  Vec3 force = Vec3::Zero();        // N      tyre force on the car, world
  double fx = 0.0, fy = 0.0;        // N      in the tyre frame
  double slip_ratio = 0.0;          // -      (omega r - v_x) / |v_x|
  // the slip angle's arguments: atan(v_y / |v_x|) is slipAngle(), taken
  // only where it is read (telemetry), not in every force evaluation
  double slip_vy = 0.0, slip_vx = 1.0;  // m/s (v_x floored at the slip speed floor)
  double slipAngle() const { return std::atan2(slip_vy, slip_vx); }  // rad
  double travel = 0.0;              // m      + = compression
  double steer = 0.0;               // rad
  double drive_torque = 0.0, brake_torque = 0.0;  // N m applied
  // for the semi-implicit deflection update: tyre frame and contact offset
  Vec3 tx = Vec3::UnitX(), ty = Vec3::UnitY(), r = Vec3::Zero();
  bool contact = false;
  double hold = 0.0;                // 0..1: how far the deflection's growth is stopped (sliding near standstill)
};

struct RoadCarOut {
  double engine_rpm = 0.0;
  double drive_power = 0.0;         // W      at the wheels
  std::array<RoadWheelOut, 4> wheel{};
};

constexpr int kRoadCarStates = 20;
inline int roadAux(int wheel, int k) { return 5 * wheel + k; }  // k: 0 s, 1 s', 2 omega, 3 u_x, 4 u_y

}  // namespace groundsim
