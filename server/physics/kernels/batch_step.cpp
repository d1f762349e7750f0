#include "physics/kernels/batch_step.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/checks/diagnostics.hpp"
#include "physics/kernels/fast_car_kernel.hpp"
#include "physics/simulator.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

namespace {

using fastcar::v4d;
using L4 = fastcar::Lane<v4d>;
constexpr int kLanes = BatchStep::kLanes;

// One group of four cars: state components as lanes, the step's inputs.
struct Group {
  // (state size) now, and before the current step; (nwheel) inputs
  std::vector<fastcar::Slot> y_, prev_, drive_, brake_, steer_;
  v4d* y() { return &y_.data()->v; }
  v4d* prev() { return &prev_.data()->v; }
  v4d* drive() { return &drive_.data()->v; }
  v4d* brake() { return &brake_.data()->v; }
  v4d* steer() { return &steer_.data()->v; }
  alignas(32) v4d drive_work{};
  alignas(32) v4d prev_work{};
  State* car[kLanes] = {};         // nullptr: a padding lane (copy of lane 0)
  bool alive[kLanes] = {};
  std::vector<WheelControl> before[kLanes];  // applied controls before the current step
};

bool sameControl(const WheelControl& a, const WheelControl& b) {
  return a.drive_torque == b.drive_torque && a.brake_torque == b.brake_torque && a.steer == b.steer;
}

// What the health check needs, per lane: NaN where any state component is
// not finite, the deepest contact, the largest squared body speed.
struct Vitals {
  v4d bad, depth, v2;
};

// One step of one group (its substeps), then its vitals; the per-car
// bookkeeping (controls, the scalar health check) is step()'s.
GROUNDSIM_INLINE_BODY Vitals advanceBody(const FastCarPlan& P, Group& g, int ny, int substeps, double h,
                                         fastcar::Scratch<v4d>& S) {
  for (int k = 0; k < substeps; ++k)
    fastcar::advance(P, g.y(), g.drive(), g.brake(), g.steer(), h, S, &g.drive_work);
  const v4d* y = g.y();
  v4d b[4] = {L4::all(0.0), L4::all(0.0), L4::all(0.0), L4::all(0.0)};  // four chains, not one
  int i = 0;
  for (; i + 4 <= ny; i += 4)
    for (int j = 0; j < 4; ++j) b[j] += y[i + j] - y[i + j];
  for (; i < ny; ++i) b[0] += y[i] - y[i];
  Vitals v{(b[0] + b[1]) + (b[2] + b[3]), L4::all(0.0), L4::all(0.0)};
  for (const fastcar::ContactL<v4d>& c : S.con) {
    const v4d d = c.in ? c.depth : L4::all(0.0);
    v.depth = d > v.depth ? d : v.depth;
  }
  for (size_t k = 0; k < P.bodies.size(); ++k) {
    const v4d* yb = y + 13 * k;
    const v4d s2 = yb[7] * yb[7] + yb[8] * yb[8] + yb[9] * yb[9];
    v.v2 = s2 > v.v2 ? s2 : v.v2;
  }
  return v;
}
GROUNDSIM_WIDE void advanceWide(const FastCarPlan& P, Group& g, int ny, int substeps, double h,
                                fastcar::Scratch<v4d>& S, Vitals* v) {
  *v = advanceBody(P, g, ny, substeps, h, S);
}
void advanceGeneric(const FastCarPlan& P, Group& g, int ny, int substeps, double h, fastcar::Scratch<v4d>& S,
                    Vitals* v) {
  *v = advanceBody(P, g, ny, substeps, h, S);
}

}  // namespace

struct BatchStep::Impl {
  explicit Impl(const Model& m) : plan(makeFastCarPlan(m)), scratch(plan), health(m) {}
  FastCarPlan plan;
  fastcar::Scratch<v4d> scratch;
  Workspace health;  // for the scalar health check and its energy scratch
  std::vector<Group> groups;
  State probe;       // one lane as a State, for checkHealth
};

// A batch steps every environment on the fast kernel with no broad phase:
// a scene whose bodies can touch each other is stepped one by one.
const char* BatchStep::unsupported(const Model& m) {
  if (m.collisions) return "bodies of the scene can touch each other (collisions)";
  return fastCarUnsupported(m);
}

BatchStep::BatchStep(std::shared_ptr<const Model> model) : model_(std::move(model)) {
  if (!model_) throw std::invalid_argument("batch step: no model");
  if (const char* why = unsupported(*model_))
    throw std::invalid_argument(std::string("batch step: this model cannot be batched: ") + why);
  impl_ = std::make_unique<Impl>(*model_);
}

BatchStep::~BatchStep() = default;

void BatchStep::step(std::span<State> cars, long long n) {
  ptrs_.resize(cars.size());  // grows once: no allocation in steady state
  for (size_t i = 0; i < cars.size(); ++i) ptrs_[i] = &cars[i];
  step(std::span<State* const>(ptrs_), n);
}

void BatchStep::step(std::span<State* const> cars, long long n) {
  const Model& m = *model_;
  Impl& I = *impl_;
  const int ny = m.stateSize();
  const size_t nw = m.wheels.size();
  for (State* sp : cars) {
    State& s = *sp;
    if (s.y.size() != ny) throw std::invalid_argument("batch step: a state's size does not match the model");
    s.controls.resize(nw);
    s.applied.resize(nw);
    if (s.tick == 0 && s.health == Health::Ok) s.initial_energy = computeEnergy(m, s, *I.health.diagnostics).total();
  }
  if (n <= 0 || cars.empty()) return;

  // pack: car c is lane c % 4 of group c / 4; padding lanes copy lane 0
  const size_t ng = (cars.size() + kLanes - 1) / kLanes;
  I.groups.resize(ng);
  for (size_t gi = 0; gi < ng; ++gi) {
    Group& g = I.groups[gi];
    g.y_.resize(ny);
    g.prev_.resize(ny);
    g.drive_.resize(nw);
    g.brake_.resize(nw);
    g.steer_.resize(nw);
    for (int l = 0; l < kLanes; ++l) {
      const size_t c = gi * kLanes + l;
      g.car[l] = c < cars.size() ? cars[c] : nullptr;
      const State& src = g.car[l] ? *g.car[l] : *cars[gi * kLanes];
      g.alive[l] = g.car[l] && src.health == Health::Ok;
      for (int i = 0; i < ny; ++i) L4::at(g.y()[i], l) = src.y[i];
      L4::at(g.drive_work, l) = src.drive_work;
    }
  }

  const int sub = std::max(1, m.opt.substeps);
  const double dt = m.opt.dt, h = dt / sub;
  const bool wide = useWideSimd(m);
  const double max_pen = m.opt.limits.max_penetration, vmax2 = m.opt.limits.max_speed * m.opt.limits.max_speed;
  for (Group& g : I.groups) {
    bool any_alive = false;
    for (int l = 0; l < kLanes; ++l) any_alive |= g.alive[l];
    if (!any_alive) continue;
    // The commands are held for the call, so once a step's applyControls
    // leaves every lane's applied controls as they were (the steering has
    // reached its target), every later one would too: from then on the
    // group skips them and keeps its packed inputs.
    bool settled = false;
    for (long long k = 0; k < n; ++k) {
      if (!settled) {
        // controls, as Simulator::step applies them
        settled = true;
        for (int l = 0; l < kLanes; ++l) {
          State* s = g.car[l] && g.alive[l] ? g.car[l] : nullptr;
          if (!s) continue;
          g.before[l] = s->applied;  // same size each step: no allocation
          applyControls(m, dt, *s);
          for (size_t w = 0; w < nw; ++w) settled = settled && sameControl(s->applied[w], g.before[l][w]);
        }
        for (size_t w = 0; w < nw; ++w)
          for (int l = 0; l < kLanes; ++l) {
            const State* s = g.car[l] ? g.car[l] : g.car[0];
            L4::at(g.drive()[w], l) = s->applied[w].drive_torque;
            L4::at(g.brake()[w], l) = s->applied[w].brake_torque;
            L4::at(g.steer()[w], l) = s->applied[w].steer;
          }
      }
      std::copy(g.y_.begin(), g.y_.end(), g.prev_.begin());
      g.prev_work = g.drive_work;
      Vitals vit;
      if (wide) advanceWide(I.plan, g, ny, sub, h, I.scratch, &vit);
      else advanceGeneric(I.plan, g, ny, sub, h, I.scratch, &vit);
      const v4d bad = vit.bad, depth = vit.depth, v2 = vit.v2;
      for (int l = 0; l < kLanes; ++l) {
        if (!g.alive[l]) {
          for (int i = 0; i < ny; ++i) L4::at(g.y()[i], l) = L4::get(g.prev()[i], l);  // stays where it stopped
          L4::at(g.drive_work, l) = L4::get(g.prev_work, l);
          continue;
        }
        State& s = *g.car[l];
        ++s.tick;
        s.t = static_cast<double>(s.tick) * dt;
        s.drive_work = L4::get(g.drive_work, l);
        const bool energy = s.tick % Simulator::kEnergyCheckInterval == 0;
        const bool suspect = !(L4::get(bad, l) == 0.0) || L4::get(depth, l) > max_pen || L4::get(v2, l) > vmax2;
        if (!energy && !suspect) continue;
        I.probe.y.resize(ny);
        for (int i = 0; i < ny; ++i) I.probe.y[i] = L4::get(g.y()[i], l);
        I.probe.applied = s.applied;
        I.probe.drive_work = s.drive_work;
        I.probe.initial_energy = s.initial_energy;
        I.probe.health = Health::Ok;
        I.health.max_depth = L4::get(depth, l);
        if (checkHealth(m, I.probe, I.health, energy)) continue;
        // divergence is terminal: the last finite state, and the reason
        s.health = I.probe.health;
        s.health_reason = I.probe.health_reason;
        --s.tick;
        s.t = static_cast<double>(s.tick) * dt;
        s.drive_work = L4::get(g.prev_work, l);
        s.applied = g.before[l];
        for (int i = 0; i < ny; ++i) L4::at(g.y()[i], l) = L4::get(g.prev()[i], l);
        L4::at(g.drive_work, l) = s.drive_work;
        g.alive[l] = false;
      }
    }
    for (int l = 0; l < kLanes; ++l)
      if (g.car[l])
        for (int i = 0; i < ny; ++i) g.car[l]->y[i] = L4::get(g.y()[i], l);
  }
}

}  // namespace groundsim
