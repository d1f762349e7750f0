// The ring car's (ring_car.hpp) private types: the plan built once from the
// model (ring_car_plan.cpp) and the scratch one evaluation fills
// (ring_car.cpp). Only the ring-car files include it.
// Named (not file-local) so both translation units share them; the
// hot functions stay always-inline in ring_car.cpp's wrappers.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "physics/core/model.hpp"
#include "physics/kernels/fast_car.hpp"
#include "physics/kernels/fast_car_lanes.hpp"

namespace groundsim::ringcar {

using fastcar::BodyL;

constexpr int kMaxWheels = 16;

// A point not on a rim (an axle point, a chassis contact point): its world
// position, velocity and spring force are kept for the step.
struct PlainPoint {
  int body, model_point, wheel;
  double lx, ly, lz;
  int steer_wheel;  // -1: fixed
  double pivx, pivy, dx, dy;
  bool contact;
};
// Points [a0, a0 + n) of one body (a wheel's rim), each joined by one spring
// of every fan to the fan's far point (an axle point, plain).
// Its arrays are padded to a multiple of four with points at the wheel's
// centre on springs of zero stiffness and damping that touch nothing: they
// add exactly zero, and the 4-wide loops need no remainder.
struct Rim {
  int body = -1, a0 = 0, n = 0, nf = 0, wheel = -1;
  int padded = 0;
  int b[2] = {-1, -1};  // plain index of each fan's far point
  std::vector<double> lx, ly, lz;
  std::vector<unsigned char> contact;
  std::vector<double> k[2], c[2], rest[2];
};
struct LooseSpring {
  int a, b;  // plain indices
  double k, c, rest;
  bool isotropic;
};
struct WheelC {
  int body, carrier;
  double ax, ay, az;
};

struct Plan {
  FastCarPlan rigid;  // bodies only (mass, inverse inertia)
  std::vector<PlainPoint> plain;
  std::vector<int> plain_begin, plain_end;  // (nbody) a body's plain points
  std::vector<int> rim_begin, rim_end;      // (nbody) a body's rims, by a0
  std::vector<Rim> rims;
  std::vector<LooseSpring> loose;
  std::vector<WheelC> wheels;
  double n[3], offset, gn;  // plane H = n . p - offset, gn = |n| as the general path computes it
  double cn[3], t1[3], t2[3];  // unit normal, its tangent basis (Eigen's unitOrthogonal)
  double gravity[3];
  double stiffness, damping, scene_mu;
  bool hunt_crossley;
  int friction_iterations;
  int max_rim = 0;
};

// Builds the plan, or says why the model does not fit.
const char* buildPlan(const Model& m, Plan* P);

struct PlainL {
  double r[3], p[3], u[3], f[3];
};
// A point below the plane, as velocity_constraints.cpp's Contact; rr is
// its lever arm, the rest what the friction solve (rigid_friction.hpp) uses.
struct ContactR {
  int body, point, wheel;
  double p[3], rr[3], u[3], depth, N, mu;
  double a1[3], a2[3], b1[3], b2[3], k00, k01, k11, i00, i01, i10, i11, j0, j1;
};
// A wheel's axle: its world axis, and what the brake solve keeps of it.
struct AxleR {
  double a[3], ia[3], ic[3], bden, bi;
};

struct Scratch {
  explicit Scratch(const Plan& P, const Model& m)
      : rigid(P.rigid), plain(P.plain.size()) {
    for (auto* v : {&H, &fx, &fy, &fz, &gx, &gy, &gz}) v->assign(static_cast<size_t>(P.max_rim), 0.0);
    con.resize(m.contact_points.size());
  }
  fastcar::Scratch<double> rigid;  // bodies: R, Iw, w, F, T, vp, wp
  std::vector<PlainL> plain;
  std::vector<double> H;           // one rim's H at each point
  std::vector<double> fx, fy, fz;  // its spring force on each point (wheel frame)
  std::vector<double> gx, gy, gz;  // of which the first fan's
  std::vector<ContactR> con;  // every contact point once at most; [0, ncon) this evaluation's
  size_t ncon = 0;
  std::span<ContactR> contacts() { return {con.data(), ncon}; }
  AxleR axles[kMaxWheels];     // wheel axes (world) and brake impulses
  double brake[kMaxWheels];     // each wheel's brake torque
  double drive_power = 0.0, max_depth = 0.0;
  int sweeps = 0;
};

}  // namespace groundsim::ringcar
