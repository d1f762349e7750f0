// A road car's normalized controls in a Session stepped by hand: CarDrive
// sets the car's controls, frames carry what is commanded and applied, and
// the command timeout releases throttle and brake as it does drive_t's
// torques (steering and gear stay).
#include <gtest/gtest.h>

#include <memory>

#include "fakes.hpp"
#include "session/session.hpp"

namespace groundsim::session::test {
namespace {

const char* kSedan = R"({"name": "sedan", "duration": 5, "physics": {"dt": 0.004}, "contact": {"friction": 1.0},
  "ground": {"type": "plane"}, "vehicle": {"name": "sedan", "kind": "road_car"}})";

struct CarRig {
  explicit CarRig(const std::string& json = kSedan) {
    scenario::Scene scene = scenario::buildScene(scenario::parseScenario(json));
    SessionSetup setup;
    setup.id = "0000CAR5";
    setup.token = "t";
    setup.vehicle_names = {"sedan"};
    setup.duration = -1;
    setup.mode = Mode::Realtime;
    session = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, out, clock.now(), clock);
  }
  void run() { session->run(clock.now()); }
  CarDrive controls(double throttle, double brake, double steer) {
    CarDrive d;
    d.vehicle = 0;
    d.controls.throttle = throttle;
    d.controls.brake = brake;
    d.controls.steer = steer;
    d.received = clock.now();
    return d;
  }
  ServiceConfig cfg;
  ManualClock clock;
  RecordingOutput out;
  std::shared_ptr<Session> session;
};

TEST(RoadCarSession, VehiclesKnowTheirRoadCar) {
  CarRig rig;
  ASSERT_EQ(rig.session->vehicles().size(), 1u);
  EXPECT_EQ(rig.session->vehicles()[0].road_car, 0);
  EXPECT_EQ(rig.session->vehicles()[0].gears, 6);  // the default gearbox
  CarRig report(carScenario());
  EXPECT_EQ(report.session->vehicles()[0].road_car, -1);
}

TEST(RoadCarSession, ControlsReachTheCarAndItsFrames) {
  CarRig rig;
  rig.run();
  ASSERT_EQ(rig.out.frames.size(), 1u);
  ASSERT_EQ(rig.out.frames[0].cars.size(), 1u);
  EXPECT_EQ(rig.out.frames[0].cars[0].commanded.throttle, 0.0);
  rig.session->post(rig.controls(1.0, 0.0, 0.25));
  rig.clock.advance(0.2);
  rig.run();
  const Frame& f = rig.out.frames.back();
  ASSERT_EQ(f.cars.size(), 1u);
  EXPECT_EQ(f.cars[0].vehicle, 0);
  EXPECT_EQ(f.cars[0].commanded.throttle, 1.0);
  EXPECT_EQ(f.cars[0].commanded.steer, 0.25);
  EXPECT_EQ(f.cars[0].applied.applied.throttle, 1.0);
  EXPECT_GE(f.cars[0].applied.gear, 1);
  EXPECT_GT(f.vehicles[0].speed, 0.1);  // 0.2 s of full throttle from rest
  // a frame of the report's car carries no road car
  CarRig report(carScenario());
  report.run();
  EXPECT_TRUE(report.out.frames.at(0).cars.empty());
}

TEST(RoadCarSession, CommandTimeoutReleasesThrottleAndBrake) {
  CarRig rig;
  rig.run();
  rig.session->post(rig.controls(0.8, 0.0, -0.5));
  rig.clock.advance(0.4);  // within the 0.5 s timeout
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 0);
  EXPECT_EQ(rig.out.frames.back().cars.at(0).commanded.throttle, 0.8);
  rig.clock.advance(0.2);  // 0.6 s after the command
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 1);
  rig.clock.advance(0.1);
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 1) << "one warning per expiry";
  const CarFrame& c = rig.out.frames.back().cars.at(0);
  EXPECT_EQ(c.commanded.throttle, 0.0);
  EXPECT_EQ(c.commanded.brake, 0.0);
  EXPECT_EQ(c.commanded.steer, -0.5);  // steering stays, as drive_t's does
  bool named = false;
  for (const Event& e : rig.out.events) named = named || e.reason.find("throttle and brake") != std::string::npos;
  EXPECT_TRUE(named);
}

// Paused time is no one's silence: a command held across a pause keeps
// its pedals for the timeout counted from the resume (a bot commands as
// the clock runs: it would otherwise lose them at every resume); the
// timeout still releases them when the silence goes on after it.
TEST(RoadCarSession, APauseDoesNotCountTowardsTheCommandTimeout) {
  CarRig rig;
  rig.run();
  rig.session->post(rig.controls(0.8, 0.0, 0.0));
  rig.clock.advance(0.1);
  rig.run();
  Request pause;
  pause.op = Op::Pause;
  pause.session_id = "0000CAR5";
  pause.token = "t";
  rig.session->post(pause);
  rig.run();
  rig.clock.advance(3.0);  // paused for 3 s of wall time
  rig.run();
  Request resume = pause;
  resume.op = Op::Resume;
  rig.session->post(resume);
  rig.run();
  rig.clock.advance(0.3);
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 0);
  EXPECT_EQ(rig.out.frames.back().cars.at(0).commanded.throttle, 0.8);
  rig.clock.advance(0.3);  // 0.6 s after the resume
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 1);
  EXPECT_EQ(rig.out.frames.back().cars.at(0).commanded.throttle, 0.0);
}

}  // namespace
}  // namespace groundsim::session::test

namespace groundsim::session::test {
namespace {

// A scripted manoeuvre in a server session: the table's rows apply as
// simulated time passes (as in `groundsim run`) until a client drives the
// car; after that the table no longer overrides the client.
TEST(RoadCarSession, ControlTableIsFollowedUntilAClientDrives) {
  const char* scripted = R"({"name": "scripted", "duration": 5, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicle": {"name": "sedan", "kind": "road_car",
                "controls": [{"t": 0, "throttle": 1}, {"t": 0.1, "throttle": 0, "brake": 0.5}]}})";
  scenario::Scene scene = scenario::buildScene(scenario::parseScenario(std::string(scripted)));
  CarRig rig;  // for its clock, config and output
  SessionSetup setup;
  setup.id = "0000CAR6";
  setup.token = "t";
  setup.vehicle_names = {"sedan"};
  setup.duration = -1;
  setup.control_tables = scene.control_tables;
  auto s = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, rig.cfg, rig.out,
                                     rig.clock.now(), rig.clock);
  s->run(rig.clock.now());
  rig.clock.advance(0.2);  // real time: 0.2 s simulated, past the second row
  s->run(rig.clock.now());
  ASSERT_FALSE(rig.out.frames.empty());
  EXPECT_EQ(rig.out.frames.back().cars.at(0).applied.applied.throttle, 0.0);
  EXPECT_EQ(rig.out.frames.back().cars.at(0).applied.applied.brake, 0.5);
  s->post(rig.controls(0.3, 0.0, 0.0));
  rig.clock.advance(0.2);
  s->run(rig.clock.now());
  EXPECT_EQ(rig.out.frames.back().cars.at(0).applied.applied.throttle, 0.3);
  EXPECT_EQ(rig.out.frames.back().cars.at(0).applied.applied.brake, 0.0);
}

}  // namespace
}  // namespace groundsim::session::test

namespace groundsim::session::test {
namespace {

// Two players in one session (issue: one frozen player cannot drive on):
// A holds full throttle and goes silent; B keeps sending controls. Each
// car's controls expire on their own: B's commands neither refresh A's
// timeout nor release A's pedals, A's release (after the timeout, within a
// frame) touches only A's car, and it is an applied entry naming A's car,
// which re-applied to a fresh simulation releases A's car only.
TEST(RoadCarSession, EachCarsControlsExpireOnTheirOwn) {
  const char* two = R"({"name": "two", "duration": 5, "physics": {"dt": 0.004}, "contact": {"friction": 1.0},
    "ground": {"type": "plane"}, "vehicles": [
      {"name": "a", "kind": "road_car", "initial": {"position": [0, 0, 0]}},
      {"name": "b", "kind": "road_car", "initial": {"position": [0, 10, 0]}}]})";
  CarRig rig(two);
  ASSERT_EQ(rig.session->vehicles().size(), 2u);
  auto drive = [&](int v, double throttle) {
    CarDrive d = rig.controls(throttle, 0.0, 0.0);
    d.vehicle = v;
    rig.session->post(d);
  };
  auto commanded = [&](int v) { return rig.out.frames.back().cars.at(static_cast<size_t>(v)).commanded.throttle; };
  rig.run();
  drive(0, 1.0);  // A: full throttle, then nothing more
  drive(1, 0.0);  // B: throttle 0 (a command with both pedals at zero cleared the whole session's flag before)
  const double timeout = rig.cfg.command_timeout;
  // B keeps driving every 0.1 s: at zero, then at half throttle
  double t = 0.0;
  for (int k = 1; t + 0.1 <= timeout - 0.05; ++k) {
    rig.clock.advance(0.1);
    t += 0.1;
    drive(1, k < 3 ? 0.0 : 0.5);
    rig.run();
  }
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 0) << "within the timeout";
  EXPECT_EQ(commanded(0), 1.0) << "A's throttle held within its timeout";
  // past A's timeout by less than a frame (50 Hz): B still sending
  const double frame = 1.0 / 50.0;
  while (t <= timeout + 0.5 * frame) {
    rig.clock.advance(0.5 * frame);
    t += 0.5 * frame;
    drive(1, 0.5);
    rig.run();
  }
  rig.clock.advance(frame);
  drive(1, 0.5);
  rig.run();
  EXPECT_EQ(commanded(0), 0.0) << "A's throttle released within the timeout plus one frame, B driving all along";
  EXPECT_EQ(commanded(1), 0.5) << "B's car untouched by A's release";
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 1);
  bool named = false;
  for (const Event& e : rig.out.events) named = named || e.reason.find("(vehicle 0) for") != std::string::npos;
  EXPECT_TRUE(named) << "the warning names the silent car";
  // the release is an applied entry of A's car only
  int releases = 0;
  for (const Applied& a : rig.out.applied)
    if (a.kind == AppliedKind::ControlsTimeout) {
      ++releases;
      EXPECT_EQ(a.vehicle, 0);
    }
  EXPECT_EQ(releases, 1);
  // re-applied (re-simulation, a standby): A's pedals released, B's kept
  scenario::Scene scene = scenario::buildScene(scenario::parseScenario(std::string(two)));
  Simulator sim(scene.built.model, scene.built.initial);
  DrivenCars cars;
  const std::vector<VehicleWheels> vw = vehicleWheels(*scene.built.model);
  for (int v : {0, 1}) {
    Applied c;
    c.kind = AppliedKind::Controls;
    c.vehicle = v;
    c.controls.throttle = 0.7;
    ASSERT_EQ(applyEntry(sim, cars, vw, scene.built.initial, c), "");
  }
  Applied release;
  release.kind = AppliedKind::ControlsTimeout;
  release.vehicle = 0;
  ASSERT_EQ(applyEntry(sim, cars, vw, scene.built.initial, release), "");
  EXPECT_EQ(sim.carControls(0).throttle, 0.0);
  EXPECT_EQ(sim.carControls(1).throttle, 0.7);
  release.vehicle = 5;
  EXPECT_NE(applyEntry(sim, cars, vw, scene.built.initial, release), "") << "a car the scenario lacks is refused";
}

}  // namespace
}  // namespace groundsim::session::test
