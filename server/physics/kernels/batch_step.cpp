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

// What every step of one call shares.
struct Stepping {
  int ny, sub;
  size_t nw;
  double dt, h;
  bool wide;
  double max_pen, vmax2;
};

Stepping stepping(const Model& m) {
  Stepping st;
  st.ny = m.stateSize();
  st.nw = m.wheels.size();
  st.sub = std::max(1, m.opt.substeps);
  st.dt = m.opt.dt;
  st.h = st.dt / st.sub;
  st.wide = useWideSimd(m.opt.deterministic);
  st.max_pen = m.opt.limits.max_penetration;
  st.vmax2 = m.opt.limits.max_speed * m.opt.limits.max_speed;
  return st;
}

// Every state of the model's size, with a control and an applied control
// per wheel; those at tick 0 get their initial energy.
void prepareCars(const Model& m, std::span<State* const> cars, const Stepping& st, Workspace& health) {
  for (State* sp : cars) {
    State& s = *sp;
    if (s.y.size() != st.ny) throw std::invalid_argument("batch step: a state's size does not match the model");
    s.controls.resize(st.nw);
    s.applied.resize(st.nw);
    if (s.tick == 0 && s.health == Health::Ok) s.initial_energy = computeEnergy(m, s, *health.diagnostics).total();
  }
}

bool anyAlive(const Group& g) {
  bool any_alive = false;
  for (int l = 0; l < kLanes; ++l) any_alive |= g.alive[l];
  return any_alive;
}

// The controls, as Simulator::step applies them, for every live lane, and
// packed as the group's inputs. Whether they were left as they were.
bool applyGroupControls(const Model& m, const Stepping& st, Group& g) {
  bool settled = true;
  for (int l = 0; l < kLanes; ++l) {
    State* s = g.car[l] && g.alive[l] ? g.car[l] : nullptr;
    if (!s) continue;
    g.before[l] = s->applied;  // same size each step: no allocation
    applyControls(m, st.dt, *s);
    for (size_t w = 0; w < st.nw; ++w) settled = settled && sameControl(s->applied[w], g.before[l][w]);
  }
  for (size_t w = 0; w < st.nw; ++w)
    for (int l = 0; l < kLanes; ++l) {
      const State* s = g.car[l] ? g.car[l] : g.car[0];
      L4::at(g.drive()[w], l) = s->applied[w].drive_torque;
      L4::at(g.brake()[w], l) = s->applied[w].brake_torque;
      L4::at(g.steer()[w], l) = s->applied[w].steer;
    }
  return settled;
}

// Lane l's configuration back to before the current step.
void rewindLane(Group& g, int l, int ny) {
  for (int i = 0; i < ny; ++i) L4::at(g.y()[i], l) = L4::get(g.prev()[i], l);
}

// The group's lanes back into their states.
void unpack(Group& g, int ny) {
  for (int l = 0; l < kLanes; ++l)
    if (g.car[l])
      for (int i = 0; i < ny; ++i) g.car[l]->y[i] = L4::get(g.y()[i], l);
}

}  // namespace

struct BatchStep::Impl {
  explicit Impl(const Model& m) : plan(makeFastCarPlan(m)), scratch(plan), health(m) {}
  FastCarPlan plan;
  fastcar::Scratch<v4d> scratch;
  Workspace health;  // for the scalar health check and its energy scratch
  std::vector<Group> groups;
  State probe;       // one lane as a State, for checkHealth

  void pack(std::span<State* const> cars, const Stepping& st);
  void runGroup(const Model& m, Group& g, long long n, const Stepping& st);
  Vitals advance(Group& g, const Stepping& st);
  void afterStep(const Model& m, Group& g, int l, const Vitals& vit, const Stepping& st);
  bool laneHealthy(const Model& m, Group& g, int l, const State& s, const Vitals& vit, bool energy, int ny);
  void stopLane(Group& g, int l, State& s, const Stepping& st);
};

// Car c is lane c % 4 of group c / 4; padding lanes copy lane 0.
void BatchStep::Impl::pack(std::span<State* const> cars, const Stepping& st) {
  const int ny = st.ny;
  const size_t nw = st.nw;
  const size_t ng = (cars.size() + kLanes - 1) / kLanes;
  groups.resize(ng);
  for (size_t gi = 0; gi < ng; ++gi) {
    Group& g = groups[gi];
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
}

// n steps of one group, then its lanes back into their states.
void BatchStep::Impl::runGroup(const Model& m, Group& g, long long n, const Stepping& st) {
  // The commands are held for the call, so once a step's applyControls
  // leaves every lane's applied controls as they were (the steering has
  // reached its target), every later one would too: from then on the
  // group skips them and keeps its packed inputs.
  bool settled = false;
  for (long long k = 0; k < n; ++k) {
    if (!settled) settled = applyGroupControls(m, st, g);
    const Vitals vit = advance(g, st);
    for (int l = 0; l < kLanes; ++l) afterStep(m, g, l, vit, st);
  }
  unpack(g, st.ny);
}

// One step of the group (its substeps) from a copy of where it was.
Vitals BatchStep::Impl::advance(Group& g, const Stepping& st) {
  std::copy(g.y_.begin(), g.y_.end(), g.prev_.begin());
  g.prev_work = g.drive_work;
  Vitals vit;
  if (st.wide) advanceWide(plan, g, st.ny, st.sub, st.h, scratch, &vit);
  else advanceGeneric(plan, g, st.ny, st.sub, st.h, scratch, &vit);
  return vit;
}

// Lane l after a step: a stopped lane stays where it stopped; a live one
// counts the step and, every kEnergyCheckInterval steps or when its vitals
// look suspect, takes the scalar health check.
void BatchStep::Impl::afterStep(const Model& m, Group& g, int l, const Vitals& vit, const Stepping& st) {
  if (!g.alive[l]) {
    rewindLane(g, l, st.ny);  // stays where it stopped
    L4::at(g.drive_work, l) = L4::get(g.prev_work, l);
    return;
  }
  State& s = *g.car[l];
  ++s.tick;
  s.t = static_cast<double>(s.tick) * st.dt;
  s.drive_work = L4::get(g.drive_work, l);
  const bool energy = s.tick % Simulator::kEnergyCheckInterval == 0;
  const bool suspect =
      !(L4::get(vit.bad, l) == 0.0) || L4::get(vit.depth, l) > st.max_pen || L4::get(vit.v2, l) > st.vmax2;
  if (!energy && !suspect) return;
  if (laneHealthy(m, g, l, s, vit, energy, st.ny)) return;
  stopLane(g, l, s, st);
}

// checkHealth on lane l as a State (the probe).
bool BatchStep::Impl::laneHealthy(const Model& m, Group& g, int l, const State& s, const Vitals& vit, bool energy,
                                  int ny) {
  probe.y.resize(ny);
  for (int i = 0; i < ny; ++i) probe.y[i] = L4::get(g.y()[i], l);
  probe.applied = s.applied;
  probe.drive_work = s.drive_work;
  probe.initial_energy = s.initial_energy;
  probe.health = Health::Ok;
  health.max_depth = L4::get(vit.depth, l);
  return checkHealth(m, probe, health, energy);
}

// Divergence is terminal: the last finite state, and the reason.
void BatchStep::Impl::stopLane(Group& g, int l, State& s, const Stepping& st) {
  s.health = probe.health;
  s.health_reason = probe.health_reason;
  --s.tick;
  s.t = static_cast<double>(s.tick) * st.dt;
  s.drive_work = L4::get(g.prev_work, l);
  s.applied = g.before[l];
  rewindLane(g, l, st.ny);
  L4::at(g.drive_work, l) = s.drive_work;
  g.alive[l] = false;
}

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
  const Stepping st = stepping(m);
  prepareCars(m, cars, st, I.health);
  if (n <= 0 || cars.empty()) return;
  I.pack(cars, st);
  for (Group& g : I.groups)
    if (anyAlive(g)) I.runGroup(m, g, n, st);
}

}  // namespace groundsim
