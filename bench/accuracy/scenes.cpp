#include "scenes.hpp"

#include <cmath>
#include <numbers>

#include "physics/build/model_builder.hpp"
#include "support/scenes.hpp"

namespace groundsim::accuracy {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.8;

GroundPtr space() { return makePlane(Vec3::UnitZ(), -1e6); }

Result begin(const std::string& scene, const Setting& s, bool fidelity) {
  Result r;
  r.scene = scene;
  r.setting = s;
  r.uses_fidelity = fidelity;
  return r;
}

void finish(Result& r, double value, double expected, bool relative) {
  r.value = value;
  r.expected = expected;
  r.error = relative ? std::abs(value - expected) / std::abs(expected) : std::abs(value - expected);
  r.error_unit = relative ? "rel" : "m";
}

BuiltModel car(const Options& o, GroundPtr g, Fidelity f, const CarPlacement& at = {}) {
  ModelBuilder b(o, std::move(g));
  addCar(b, "car", carParams(f), at);
  return b.build();
}

// Car scenes share the report's ground (2000 N/m) with light damping so
// that the continuous wheel settles; the friction is the scene's.
Options carOptions(double mu) {
  Options o;
  o.contact.friction = mu;
  o.contact.damping = 20.0;
  return o;
}

// ---- analytic scenes ----

Result freeFall(const Setting& s) {
  Result r = begin("free_fall", s, false);
  Options o = s.apply(Options{});
  ModelBuilder b(o, space());
  b.addParticle(1.0, Vec3(0, 0, 100), Vec3(1, 0, 0), false);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  if (!runTo(sim, 2.0, r)) return r;
  finish(r, 100.0 - sim.state().y[2], 0.5 * kG * 4.0, true);
  return r;
}

Result springMass(const Setting& s) {
  // two masses 1 and 3 kg on a 1000 N/m spring, stretched 1 cm: the
  // stretch is 0.01 cos(omega t) with omega = sqrt(k (m1 + m2) / (m1 m2))
  Result r = begin("spring_mass", s, false);
  test::SpringPairSpec pair;
  pair.m2 = 3.0;
  pair.stiffness = 1000.0;
  pair.stretch = 0.01;
  auto built = test::springPair(s.apply(Options{}), pair);
  Simulator sim(built.model, built.initial);
  if (!runTo(sim, 2.0, r)) return r;
  const double omega = std::sqrt(1000.0 * 4.0 / 3.0), t = sim.state().t;
  const double stretch = sim.state().y[6] - sim.state().y[0] - 1.0;
  r.value = stretch;
  r.expected = 0.01 * std::cos(omega * t);
  r.error = std::abs(r.value - r.expected) / 0.01;  // relative to the amplitude
  return r;
}

// Restitution of a point hitting a Kelvin-Voigt ground with damping ratio
// zeta, no gravity: the damped oscillator until the ground force S d + c d'
// reaches zero (it never pulls).
double analyticRestitution(double S, double m, double zeta) {
  const double w = std::sqrt(S / m), wd = w * std::sqrt(1 - zeta * zeta), c = 2 * zeta * std::sqrt(S * m);
  auto depth = [&](double t) { return std::exp(-zeta * w * t) * std::sin(wd * t) / wd; };
  auto rate = [&](double t) {
    return std::exp(-zeta * w * t) * (wd * std::cos(wd * t) - zeta * w * std::sin(wd * t)) / wd;
  };
  double lo = 0.5 * kPi / wd, hi = kPi / wd;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (S * depth(mid) + c * rate(mid) > 0 ? lo : hi) = mid;
  }
  return -rate(lo);
}

Result dropBounce(const Setting& s) {
  const double S = 1e4, m = 0.5, zeta = 0.1;
  Result r = begin("drop_bounce", s, false);
  auto built = test::droppedPoint(s.apply(Options{}), m, 0.01, 1.0, S, zeta);
  Simulator sim(built.model, built.initial);
  if (!runTo(sim, 0.1, r)) return r;  // in and out (contact lasts ~0.03 s)
  finish(r, sim.state().y[5], analyticRestitution(S, m, zeta), true);
  return r;
}

// Least-squares slope of the chassis speed over [t0, t1], sampled every 10 ms.
bool fittedAcceleration(Simulator& sim, double t0, double t1, Result& r, double* a) {
  double st = 0, sv = 0, stt = 0, stv = 0;
  int n = 0;
  for (int k = 1; k * 0.01 <= t1 + 1e-9; ++k) {
    if (!runTo(sim, k * 0.01, r)) return false;
    const double t = sim.state().t;
    if (t < t0 - 1e-9) continue;
    const double v = bodyVel(sim.state().y, 0).norm();
    st += t; sv += v; stt += t * t; stv += t * v; ++n;
  }
  *a = (n * stv - st * sv) / (n * stt - st * st);
  return true;
}

Result incline(const Setting& s) {
  // a = g sin(theta) M / (M + sum I_w / r^2) = 4.9 * 1.4 / 1.8
  Result r = begin("incline_30", s, true);
  auto built = car(s.apply(carOptions(0.9)), makeIncline(kPi / 6, Vec3::UnitX()), s.fidelity);
  Simulator sim(built.model, built.initial);
  double a = 0;
  if (!fittedAcceleration(sim, 0.5, 2.0, r, &a)) return r;
  finish(r, a, kG * 0.5 * 1.4 / 1.8, true);
  return r;
}

Result plainS1(const Setting& s) {
  // wheels spun to 5 rad/s: rolling without slip ends at 2.0 / 1.8 m/s
  Result r = begin("plain_s1", s, true);
  CarPlacement at;
  at.wheel_spin = 5.0;
  auto built = car(s.apply(carOptions(0.5)), makePlane(Vec3::UnitZ(), 0), s.fidelity, at);
  Simulator sim(built.model, built.initial);
  if (!runTo(sim, 5.0, r)) return r;
  finish(r, bodyVel(sim.state().y, 0).x(), 2.0 / 1.8, true);
  return r;
}

Result parked(const Setting& s) {
  // brakes on, 20 degrees, mu 0.9: after settling for 1 s the car must not
  // move in the next 3 s (creep, metres)
  Result r = begin("parked_20", s, true);
  auto built = car(s.apply(carOptions(0.9)), makeIncline(20 * kPi / 180, Vec3::UnitX()), s.fidelity);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.brake_torque = 10.0;
  if (!runTo(sim, 1.0, r)) return r;
  const Vec3 x0 = bodyPos(sim.state().y, 0);
  if (!runTo(sim, 4.0, r)) return r;
  finish(r, (bodyPos(sim.state().y, 0) - x0).norm(), 0.0, false);
  return r;
}

Result skidStop(const Setting& s) {
  // a slab on four feet at 5 m/s, mu 0.5: it stops after v^2 / (2 mu g)
  Result r = begin("skid_stop", s, false);
  Options o = s.apply(Options{});
  o.contact.stiffness = 1e5;
  o.contact.damping = 2.0 * std::sqrt(1e5 * 0.25);
  o.contact.friction = 0.5;
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  BodySpec slab;
  for (int i = 0; i < 4; ++i) {
    slab.points.push_back(Vec3(i & 1 ? 1.0 : -1.0, i & 2 ? 0.5 : -0.5, -0.2));
    slab.points.push_back(Vec3(i & 1 ? 1.0 : -1.0, i & 2 ? 0.5 : -0.5, 0.2));
    slab.masses.insert(slab.masses.end(), {0.125, 0.125});
    slab.contact.insert(slab.contact.end(), {true, false});
  }
  slab.origin = Vec3(0, 0, 0.2 - kG / 4e5);
  slab.velocity = Vec3(5, 0, 0);
  b.addBody(slab);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  if (!runTo(sim, 1.5, r)) return r;  // stops at 1.02 s
  finish(r, bodyPos(sim.state().y, 0).x(), 25.0 / (2 * 0.5 * kG), true);
  return r;
}

}  // namespace

std::vector<Scene> analyticScenes() {
  return {
      {"free_fall", "drop 2 s: g t^2 / 2 = 19.6 m", false, freeFall},
      {"spring_mass", "stretch 0.01 cos(omega t) at 2 s, error / amplitude", false, springMass},
      {"drop_bounce", "restitution of the clamped damped oscillator (zeta 0.1)", false, dropBounce},
      {"incline_30", "rolling acceleration 3.8111 m/s^2 (mu 0.9)", true, incline},
      {"plain_s1", "speed at 5 s 1.1111 m/s (mu 0.5, wheels at 5 rad/s)", true, plainS1},
      {"parked_20", "creep 0 m over 3 s, brakes on (absolute error, m)", true, parked},
      {"skid_stop", "stop distance v^2 / (2 mu g) = 2.551 m", false, skidStop},
  };
}

// ---- the report's four experiments (section 5) ----

Result runExperiment(const std::string& name, const Setting& s) {
  Result r = begin(name, s, true);
  Options o;
  GroundPtr g;
  CarPlacement at;
  double T = 0, torque = 0;
  if (name == "exp_plain") {
    o = carOptions(0.5);
    g = makePlane(Vec3::UnitZ(), 0);
    at.wheel_spin = 5.0;
    T = 5.0;
  } else if (name == "exp_downhill") {
    o = carOptions(0.9);
    g = makeIncline(kPi / 6, Vec3::UnitX());
    T = 2.0;
  } else if (name == "exp_uphill") {
    o = carOptions(0.9);
    g = makeIncline(kPi / 18, -Vec3::UnitX());
    at.wheel_spin = 2.0;
    torque = 1.5;
    T = 3.0;
  } else {  // exp_cosine
    o = carOptions(0.5);
    g = makeCosineWave(0.5, 2 * kPi);
    at.position = Vec3(kPi, 0, 0);
    at.wheel_spin = 5.0;
    T = 5.0;
  }
  auto built = car(s.apply(o), g, s.fidelity, at);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.drive_torque = torque;
  const Vec3 x0 = bodyPos(sim.state().y, 0);
  if (!runTo(sim, T, r)) return r;
  // value: distance travelled by the chassis; error compares end positions
  r.value = (bodyPos(sim.state().y, 0) - x0).norm();
  return r;
}

std::vector<Scene> reportExperiments() {
  std::vector<Scene> out;
  for (const char* n : {"exp_plain", "exp_downhill", "exp_uphill", "exp_cosine"})
    out.push_back({n, "chassis end position vs RK4 reference at dt 1e-5", true,
                   [n](const Setting& s) { return runExperiment(n, s); }});
  return out;
}

}  // namespace groundsim::accuracy
