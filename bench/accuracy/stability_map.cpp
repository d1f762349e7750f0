// Each probe builds a scene at a trial dt and reports whether the run stays
// stable: healthy (no NaN, penetration, speed or energy alarm) and, for the
// resting mass, never leaving the ground it should rest on. Bisection then
// brackets the boundary to 2% in dt.
#include "stability_map.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include "cell.hpp"
#include "physics/build/model_builder.hpp"
#include "physics/build/vehicle.hpp"

namespace groundsim::accuracy {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
using Probe = std::function<bool(IntegratorKind, double dt)>;

// Largest dt in [lo, hi] with probe true (assumes one boundary): inf if hi
// is stable, 0 if lo is not.
double largestStable(const Probe& stable, IntegratorKind k, double lo, double hi) {
  if (stable(k, hi)) return kInf;
  if (!stable(k, lo)) return 0.0;
  while (hi / lo > 1.02) {
    const double mid = std::sqrt(lo * hi);
    (stable(k, mid) ? lo : hi) = mid;
  }
  return lo;
}

Options base(IntegratorKind k, double dt) {
  Options o;
  o.integrator = k;
  o.dt = dt;
  o.tolerance = 1e-4;
  return o;
}

// A point mass resting on the ground (1% off its sag) or a second mass on a
// spring on top of it: stable if its perturbation stays small and it stays healthy for 40
// periods of the stiffest mode (at least 2000 steps).
bool restingStack(IntegratorKind k, double dt, double S, double m_low, double m_top, double k_top,
                  double omega) {
  Options o = base(k, dt);
  o.contact.stiffness = S;
  o.contact.friction = 0.0;
  o.limits.max_penetration = 1e9;  // only lift-off and health count
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  const double g = 9.8, total = m_low + m_top;
  const double sag = total * g / S;
  b.addParticle(m_low, Vec3(0, 0, -1.01 * sag), Vec3::Zero());
  if (m_top > 0) {
    const int top = b.addParticle(m_top, Vec3(0, 0, 1.0 - sag - m_top * g / k_top), Vec3::Zero(), false);
    Spring sp;
    sp.a = 0;
    sp.b = top;
    sp.stiffness = k_top;
    sp.rest_length = 1.0;
    b.addSpring(sp);
  }
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  const long long steps = std::max<long long>(2000, std::llround(40 * 2 * kPi / omega / dt));
  for (long long i = 0; i < std::min<long long>(steps, 200000); ++i) {
    if (!sim.step()) return false;
    // the 1% perturbation grew 20x: linear instability (symplectic Euler's
    // bounded ellipse stretches it 20x only within 0.2% of omega dt = 2)
    if (std::abs(-sim.state().y[2] - sag) > 0.2 * sag) return false;
  }
  return true;
}

// Stiffest mode of the two-mass stack (ground S under m_low, k between).
double stackOmega(double S, double m_low, double m_top, double k) {
  if (m_top == 0) return std::sqrt(S / m_low);
  Eigen::Matrix2d K, Minv;
  K << S + k, -k, -k, k;
  Minv << 1 / m_low, 0, 0, 1 / m_top;
  const Eigen::Matrix2d A = Minv * K;
  return std::sqrt(A.eigenvalues().real().maxCoeff());
}

// The report's car (circle wheels, bearings) run for `T` s; stable if healthy.
bool carRun(IntegratorKind k, double dt, double T, const GroundPtr& g, const CarPlacement& at,
            double stiffness = 2000.0, double brake = 0.0) {
  Options o = base(k, dt);
  o.contact.stiffness = stiffness;
  o.contact.damping = 20.0;
  o.contact.friction = 0.9;
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.coupling = WheelCoupling::Bearing;
  ModelBuilder b(o, g);
  addCar(b, "car", p, at);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.brake_torque = brake;
  return sim.step(std::llround(T / dt));
}

// A point dropped from 100 m onto a 1e6 N/m ground: stable if it is healthy
// after the first bounce and rises no higher than it fell from.
bool drop100(IntegratorKind k, double dt) {
  Options o = base(k, dt);
  o.contact.stiffness = 1e6;
  o.contact.friction = 0.0;
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  b.addParticle(1.0, Vec3(0, 0, 100), Vec3::Zero());
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  double top_after = 0;
  bool bounced = false;
  const long long steps = std::llround(9.5 / dt);  // impact at 4.52 s, apex again near 9 s
  for (long long i = 0; i < steps; ++i) {
    if (!sim.step()) return false;
    const double z = sim.state().y[2];
    if (z < 0) bounced = true;
    if (bounced) top_after = std::max(top_after, z);
  }
  return bounced && top_after <= 100.0 * 1.001;
}

const IntegratorKind kMethods[] = {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet,
                                   IntegratorKind::Rk4, IntegratorKind::ImplicitEuler, IntegratorKind::Adaptive};

std::string sci(const char* name, double v, const char* unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s=%.0e%s", name, v, unit);
  return buf;
}

}  // namespace

std::vector<StabilityRow> stabilityMap(bool quick) {
  std::vector<StabilityRow> rows;
  auto theoryFor = [](IntegratorKind k, double omega) {
    if (k == IntegratorKind::SemiImplicitEuler || k == IntegratorKind::VelocityVerlet) return 2.0 / omega;
    if (k == IntegratorKind::Rk4) return 2.0 * std::sqrt(2.0) / omega;
    return kInf;
  };
  // 1. ground stiffness, 1 kg resting
  for (double S = 1e2; S <= 1e8 * 1.01; S *= quick ? 100 : 10) {
    const double w = std::sqrt(S);
    for (IntegratorKind k : kMethods) {
      if (k == IntegratorKind::ImplicitEuler && S > 1e6 && quick) continue;
      const Probe p = [&](IntegratorKind kk, double dt) { return restingStack(kk, dt, S, 1.0, 0, 0, w); };
      rows.push_back({"ground_stiffness", sci("k", S, " N/m"), k,
                      largestStable(p, k, 0.1 / w, std::min(100.0 / w, 1.0)), theoryFor(k, w), w, ""});
    }
  }
  // 2. mass ratio: a light 1 kg mass on the ground (1e4 N/m) carrying a heavy
  //    one on a 1e5 N/m spring; ratio heavy/light up to 1e4
  for (double ratio : quick ? std::vector<double>{1, 1e4} : std::vector<double>{1, 1e2, 1e3, 1e4}) {
    const double S = 1e4 * (1 + ratio), kt = 1e5;  // ground stiffened to carry the stack
    const double w = stackOmega(S, 1.0, ratio, kt);
    for (IntegratorKind k : kMethods) {
      const Probe p = [&](IntegratorKind kk, double dt) { return restingStack(kk, dt, S, 1.0, ratio, kt, w); };
      rows.push_back({"mass_ratio", sci("ratio", ratio, ""), k,
                      largestStable(p, k, 0.1 / w, std::min(100.0 / w, 1.0)), theoryFor(k, w), w,
                      "ground 1e4 (1 + ratio) N/m, spring 1e5 N/m"});
    }
  }
  // 3. speed: the car (circle wheels) rolling at up to 100 m/s on the plain
  for (double v : quick ? std::vector<double>{100} : std::vector<double>{10, 30, 100}) {
    CarPlacement at;
    at.speed = v;
    at.wheel_spin = v;  // radius 1 m: rolling
    for (IntegratorKind k : kMethods) {
      if (k == IntegratorKind::ImplicitEuler) continue;  // n + 1 evaluations per step: too slow to bisect
      const Probe p = [&](IntegratorKind kk, double dt) {
        return carRun(kk, dt, 2.0, makePlane(Vec3::UnitZ(), 0), at);
      };
      rows.push_back({"speed", sci("v", v, " m/s"), k, largestStable(p, k, 1e-5, 1e-2), 0, 0,
                      "report car, circle wheels, 2 s"});
    }
  }
  // 4. a drop from 100 m onto a 1e6 N/m ground (impact 44 m/s)
  for (IntegratorKind k : kMethods) {
    if (k == IntegratorKind::ImplicitEuler) {
      rows.push_back({"drop_100m", "k=1e6 N/m", k, largestStable(drop100, k, 1e-4, 1e-1), 0, 1e3,
                      "implicit Euler absorbs the bounce"});
      continue;
    }
    rows.push_back({"drop_100m", "k=1e6 N/m", k, largestStable(drop100, k, 1e-5, 1e-1), theoryFor(k, 1e3), 1e3,
                    "bouncing contact: below the resting bound"});
  }
  // 5. slopes up to 80 degrees: the car released from rest (it slides above
  //    atan(0.9) = 42 degrees)
  for (double deg : quick ? std::vector<double>{80} : std::vector<double>{20, 40, 60, 80}) {
    for (IntegratorKind k : kMethods) {
      if (k == IntegratorKind::ImplicitEuler) continue;
      const Probe p = [&](IntegratorKind kk, double dt) {
        return carRun(kk, dt, 2.0, makeIncline(deg * kPi / 180, Vec3::UnitX()), CarPlacement{});
      };
      rows.push_back({"slope", sci("deg", deg, ""), k, largestStable(p, k, 1e-5, 1e-2), 0, 0,
                      "report car, circle wheels, 2 s"});
    }
  }
  return rows;
}

}  // namespace groundsim::accuracy
