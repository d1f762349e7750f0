// The mutable state: small and complete. Copying it and stepping the copy
// gives bit-identical results to stepping the original.
//
// y is one flat vector so that every integrator is generic over it:
//   body i     at 13 i:        x (3, m) | q (4, quaternion x y z w) | v (3, m/s) | L (3, N m s, world)
//   particle j at 13 nb + 6 j: x (3, m) | v (3, m/s)
//   road car c at 13 nb + 6 np + 20 c: per wheel s, ds/dt, omega, u_x, u_y (road_car.hpp)
// Angular momentum (not angular velocity) is the state, as in the report's
// eq. (20): with no torque it is conserved exactly by every integrator.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "physics/base/math.hpp"
#include "physics/road_car/road_car.hpp"

namespace groundsim {

struct WheelControl {
  double drive_torque = 0.0;  // N m   about the wheel axle, reaction on the carrier
  double brake_torque = 0.0;  // N m   largest torque the brake may exert (>= 0)
  double steer = 0.0;         // rad   steering angle (steerable wheels only)
};

enum class Health { Ok, NonFinite, Penetration, Speed, Energy };
const char* healthName(Health h);

struct State {
  Eigen::VectorXd y;
  double t = 0.0;              // s
  std::int64_t tick = 0;       // steps taken
  double h_next = 0.0;         // s     adaptive integrator's next trial step
  double drive_work = 0.0;     // J     work done by drive torques (energy bookkeeping)
  double initial_energy = 0.0; // J
  std::vector<WheelControl> controls;  // as commanded
  // as applied this step: drive and brake as commanded (brake >= 0), the
  // steering angle clamped to the wheel's range and moved towards the
  // command at the wheel's steering rate (an instant turn would snap the
  // axle points and fling the rim springs)
  std::vector<WheelControl> applied;
  std::vector<CarControls> car_controls;  // (nroadcar) as commanded
  std::vector<CarRuntime> cars;           // (nroadcar) as applied, gear (road_car.hpp)
  Health health = Health::Ok;
  std::string health_reason;
};

// Views into y.
inline Eigen::Map<Vec3> bodyPos(Eigen::VectorXd& y, int i) { return Eigen::Map<Vec3>(y.data() + 13 * i); }
inline Eigen::Map<Quat> bodyRot(Eigen::VectorXd& y, int i) { return Eigen::Map<Quat>(y.data() + 13 * i + 3); }
inline Eigen::Map<Vec3> bodyVel(Eigen::VectorXd& y, int i) { return Eigen::Map<Vec3>(y.data() + 13 * i + 7); }
inline Eigen::Map<Vec3> bodyMom(Eigen::VectorXd& y, int i) { return Eigen::Map<Vec3>(y.data() + 13 * i + 10); }
inline Eigen::Map<const Vec3> bodyPos(const Eigen::VectorXd& y, int i) { return Eigen::Map<const Vec3>(y.data() + 13 * i); }
inline Eigen::Map<const Quat> bodyRot(const Eigen::VectorXd& y, int i) { return Eigen::Map<const Quat>(y.data() + 13 * i + 3); }
inline Eigen::Map<const Vec3> bodyVel(const Eigen::VectorXd& y, int i) { return Eigen::Map<const Vec3>(y.data() + 13 * i + 7); }
inline Eigen::Map<const Vec3> bodyMom(const Eigen::VectorXd& y, int i) { return Eigen::Map<const Vec3>(y.data() + 13 * i + 10); }
inline int particleOffset(int nbodies, int j) { return 13 * nbodies + 6 * j; }

}  // namespace groundsim
