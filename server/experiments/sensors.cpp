// Resolution (task -> sensors, once per model) and reading (one case per
// kind). Definitions of every feature: docs/scenario.md, "Tasks".
#include "experiments/sensors.hpp"

#include <cmath>

#include "drivers/track_course.hpp"
#include "experiments/env.hpp"
#include "physics/ground/ground.hpp"
#include "physics/road_car/road_car.hpp"

namespace groundsim::experiments {
namespace {

using scenario::Feature;
using Kind = Sensor::Kind;

Vec3 omegaWorld(const Model& m, const Eigen::VectorXd& y, int b) {
  const Mat3 R = bodyRotation(y, b);
  return R * (m.bodies[static_cast<size_t>(b)].inv_inertia * (R.transpose() * Vec3(bodyMom(y, b))));
}

// The four wheels of the task's vehicle for a per-wheel feature: a road
// car's (by road-car index), or the model wheels of a report car (Zero
// where it has fewer than four).
void perWheel(const Agent& agent, int slot, Kind road, Kind wheel, std::vector<Sensor>& out) {
  for (int k = 0; k < 4; ++k) {
    Sensor s;
    s.slot = slot + k;
    s.wheel = k;
    const int wi = agent.wheels[static_cast<size_t>(k)];
    if (agent.road_car >= 0) {
      s.kind = road;
      s.index = agent.road_car;
    } else if (wi >= 0) {
      s.kind = wheel;
      s.index = wi;
    }
    out.push_back(s);
  }
}

}  // namespace

Mat3 bodyRotation(const Eigen::VectorXd& y, int b) { return bodyRot(y, b).normalized().toRotationMatrix(); }

std::vector<Sensor> resolveSensors(const TaskContext& ctx, int agent, const Model& m) {
  const scenario::TaskSpec& t = ctx.task();
  const Agent& me = ctx.agents[static_cast<size_t>(agent)];
  std::vector<Sensor> out;
  int slot = 0;
  auto add = [&](Kind kind, int width, int index = 0) {
    Sensor s;
    s.kind = kind;
    s.slot = slot;
    s.index = index;
    out.push_back(s);
    slot += width;
  };
  // a road car's per-wheel state entries: spin (2) or strut travel (0)
  auto roadEntries = [&](int which) {
    for (int k = 0; k < 4; ++k)
      add(Kind::StateEntry, 1, m.auxBase() + m.road_cars[static_cast<size_t>(me.road_car)].aux + roadAux(k, which));
  };
  for (Feature f : t.observation) {
    switch (f) {
      case Feature::Position: add(Kind::Position, 3); break;
      case Feature::Heading: add(Kind::Heading, 2); break;
      case Feature::UpBody: add(Kind::UpBody, 3); break;
      case Feature::VelocityBody: add(Kind::VelocityBody, 3); break;
      case Feature::AngularVelocityBody: add(Kind::AngularVelocityBody, 3); break;
      case Feature::Speed: add(Kind::Speed, 1); break;
      case Feature::WheelSpin:
        if (me.road_car >= 0) roadEntries(2);
        else {
          perWheel(me, slot, Kind::Zero, Kind::WheelSpin, out);
          slot += 4;
        }
        break;
      case Feature::WheelContact:
        perWheel(me, slot, Kind::RoadContact, Kind::WheelContact, out);
        slot += 4;
        break;
      case Feature::WheelSlip:
        perWheel(me, slot, Kind::RoadSlip, Kind::WheelSlip, out);
        slot += 4;
        break;
      case Feature::SuspensionTravel: roadEntries(0); break;  // validation: road cars only
      case Feature::HeightSamples:
        for (double a : t.height_ahead)
          for (double lat : t.height_lateral) {
            Sensor s;
            s.kind = Kind::HeightSample;
            s.slot = slot++;
            s.ahead = a;
            s.lateral = lat;
            out.push_back(s);
          }
        break;
      case Feature::GoalBody: add(Kind::GoalBody, 2); break;
      case Feature::GoalDistance: add(Kind::GoalDistance, 1); break;
      case Feature::PreviousAction:
        for (int k = 0; k < ctx.layout.actionSize(); ++k) add(Kind::PreviousAction, 1, k);
        break;
      case Feature::Time: add(Kind::Time, 1); break;
      case Feature::AgentsBody:
        for (int other = 0; other < static_cast<int>(ctx.agents.size()); ++other)
          if (other != agent) add(Kind::OtherAgent, 4, other);
        break;
      case Feature::TrackAhead: add(Kind::TrackAhead, 2 * static_cast<int>(t.track_ahead.size())); break;
      case Feature::TrackPose: add(Kind::TrackPose, 3); break;
      case Feature::TrackCurvature: add(Kind::TrackCurvature, static_cast<int>(t.track_ahead.size())); break;
      case Feature::NextGate: add(Kind::NextGate, 2); break;
    }
  }
  return out;
}

void readSensors(const std::vector<Sensor>& sensors, const TaskContext& ctx, int agent, const Model& m,
                 const State& st, const Workspace& ws, const SensorInputs& in, double* out) {
  const scenario::TaskSpec& t = ctx.task();
  const Eigen::VectorXd& y = st.y;
  const int b = ctx.agents[static_cast<size_t>(agent)].body;
  // the frame every body-relative sensor shares (the policy driver reads
  // its car through the same view: drivers/track_course.hpp)
  const drivers::BodyView car = drivers::viewBody(m, y, b);
  const Vec3& c = car.c;
  const Mat3& R = car.R;
  const Vec3& v = car.v;
  const Vec3 fwd = R.col(0);
  const double fh = std::hypot(fwd.x(), fwd.y());
  // the heading: the forward axis on the ground plane (+x when it points straight up)
  const double hc = fh > 0.0 ? fwd.x() / fh : 1.0, hs = fh > 0.0 ? fwd.y() / fh : 0.0;
  auto put3 = [out](int slot, const Vec3& x) {
    for (int i = 0; i < 3; ++i) out[slot + i] = x[i];
  };
  auto wheelSpin = [&](int wi) {
    const Wheel& wh = m.wheels[static_cast<size_t>(wi)];
    Vec3 rel = omegaWorld(m, y, wh.body);
    if (wh.carrier >= 0) rel -= omegaWorld(m, y, wh.carrier);
    return rel.dot(bodyRotation(y, wh.body) * wh.axis);
  };
  auto height = [&](const Sensor& s) {
    const double px = c.x() + s.ahead * hc - s.lateral * hs, py = c.y() + s.ahead * hs + s.lateral * hc;
    Vec3 p, normal;
    return groundPointBelow(*in.probe, px, py, &p, &normal) ? p.z() - c.z() : 0.0;
  };
  auto road = [&](const Sensor& s) -> const auto& {
    return ws.road[static_cast<size_t>(s.index)].wheel[static_cast<size_t>(s.wheel)];
  };
  for (const Sensor& s : sensors) {
    double* o = out + s.slot;
    switch (s.kind) {
      case Kind::Zero: o[0] = 0.0; break;
      case Kind::Position: put3(s.slot, c); break;
      case Kind::Heading: o[0] = hc, o[1] = hs; break;
      case Kind::UpBody: drivers::upBody(car, o); break;
      case Kind::VelocityBody: drivers::velocityBody(car, o); break;
      case Kind::AngularVelocityBody: drivers::angularVelocityBody(car, o); break;
      case Kind::Speed: o[0] = v.norm(); break;
      case Kind::StateEntry: o[0] = y[s.index]; break;
      case Kind::WheelSpin: o[0] = wheelSpin(s.index); break;
      case Kind::RoadContact: o[0] = !in.fresh && road(s).contact ? 1.0 : 0.0; break;
      case Kind::RoadSlip: o[0] = in.fresh ? 0.0 : road(s).slip_ratio; break;
      case Kind::WheelContact: o[0] = !in.fresh && ws.wheel_normal[static_cast<size_t>(s.index)] > 0.0 ? 1.0 : 0.0; break;
      case Kind::WheelSlip: o[0] = in.fresh ? 0.0 : ws.wheel_slip[static_cast<size_t>(s.index)]; break;
      case Kind::HeightSample: o[0] = height(s); break;
      case Kind::GoalBody: {
        const Vec3 d = R.transpose() * Vec3(t.goal[0] - c.x(), t.goal[1] - c.y(), 0.0);
        o[0] = d.x(), o[1] = d.y();
        break;
      }
      case Kind::GoalDistance: o[0] = std::hypot(t.goal[0] - c.x(), t.goal[1] - c.y()); break;
      case Kind::PreviousAction: o[0] = in.previous_action[s.index]; break;
      case Kind::Time: o[0] = in.time; break;
      case Kind::OtherAgent: {
        const int ob = ctx.agents[static_cast<size_t>(s.index)].body;
        const Vec3 d = R.transpose() * Vec3(bodyPos(y, ob) - c), dv = R.transpose() * Vec3(bodyVel(y, ob) - v);
        o[0] = d.x(), o[1] = d.y(), o[2] = dv.x(), o[3] = dv.y();
        break;
      }
      case Kind::TrackAhead: drivers::trackAhead(*ctx.track, *in.track, car, t.track_ahead, o); break;
      case Kind::TrackPose: drivers::trackPose(*ctx.track, *in.track, car, o); break;
      case Kind::TrackCurvature: drivers::trackCurvature(*ctx.track, *in.track, t.track_ahead, o); break;
      case Kind::NextGate: drivers::nextGate(*ctx.track, *in.track, car, o); break;
    }
  }
}

}  // namespace groundsim::experiments
