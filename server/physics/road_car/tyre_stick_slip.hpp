// The rigid stick-slip tyre (`tyres.model: "stick_slip"`, see
// tyre_stick_slip.cpp): a velocity-level friction impulse at each contact
// patch, solved together with the brakes of the same wheels.
#pragma once

#include <array>

#include <Eigen/Core>

#include "physics/road_car/road_car.hpp"

namespace groundsim {

// One wheel's part in the solve, filled by applyRoadCars before it.
struct StickSlipWheel {
  bool active = false;              // a stick-slip tyre
  bool contact = false;             // its patch touches the ground
  Vec3 tx = Vec3::UnitX(), ty = Vec3::UnitY();  // tyre frame in the ground's tangent plane
  Vec3 r_c = Vec3::Zero(), r_hub = Vec3::Zero(), axle = Vec3::UnitY();  // from the body's centre of mass
  double normal = 0.0;              // N      F_z
  double mu_static = 0.0, mu_sliding = 0.0;
  double brake_cap = 0.0;           // N m    brake (and handbrake) torque available; 0: no brake
  double spin = 0.0;                // rad/s  omega now
  double spin_rate = 0.0;           // rad/s^2 from the drive and rolling resistance alone
  double strut_rate = 0.0;          // m/s    s' now
  // results
  double fx = 0.0, fy = 0.0;        // N      patch force, tyre frame
  double brake_torque = 0.0;        // N m    on the wheel (+ = forward spin)
  bool sliding = false;
};

// The body's side of the solve: its reduced 6x6 mass matrix M (the car
// less the wheels' motion along the struts), the generalised force G
// without the stick-slip tyres' friction and brakes, and its velocities.
struct StickSlipBody {
  const Eigen::Matrix<double, 6, 6>* M = nullptr;
  Eigen::Matrix<double, 6, 1>* G = nullptr;
  Vec3 v = Vec3::Zero(), omega = Vec3::Zero();
  Vec3 gyro = Vec3::Zero();         // rad/s^2 I^-1 (omega x I omega): the momentum update's extra term
  Vec3 nb = Vec3::UnitZ();          // strut axis
  double* Q = nullptr;              // (4) along-strut force on each carrier, N
};

// Friction impulses (a friction circle of mu_static N h: stick; beyond it,
// slide at mu_sliding N opposite the slip) and brake impulses (at most
// brake_cap h, stopping the wheel at most) that leave every patch without
// slip at the end of the step h where they can. Adds their forces to G and
// Q and fills each wheel's results. No allocation.
void solveStickSlipTyres(const RoadCarParams& p, const StickSlipBody& body, double h,
                         std::array<StickSlipWheel, 4>& wheels);

// forces/road_cars.cpp's steps for a stick-slip wheel. At the patch: the tyre frame
// and friction (peak = ground mu * friction_scale, sliding = that *
// sliding_ratio), no force yet. Then its drive and brake: traction control
// caps the drive torque at mu_static F_z r (the most the patch can return
// before it slides) and ABS the brake torque at kAbsShare of it, so the
// wheel never spins up or locks; while a patch slides, they cut the drive
// or release the brake. The brake itself is solved with the friction.
inline constexpr double kAbsShare = 0.95;  // of mu_static N r: ABS's brake limit with the stick-slip tyre
void stickSlipPatch(const TyreParams& t, double Fz, double mu_ground, const Vec3& r_c, RoadWheelOut& o,
                    StickSlipWheel& ss);
void stickSlipWheel(const RoadCarParams& p, bool handbrake, double vx, double spin, double strut_rate,
                    const Vec3& r_hub, const Vec3& axle, double brake_cap, double t_rr, StickSlipWheel& ss,
                    double* t_drive);
// Solves, then books the forces and brake torques in the wheels' outputs
// and their spin rates (aux_dot: the car's 20 state rates).
void applyStickSlipTyres(const RoadCarParams& p, const StickSlipBody& body, double h,
                         std::array<StickSlipWheel, 4>& wheels, RoadCarOut& out, double* aux_dot);

}  // namespace groundsim
