// A race in a Session stepped by hand (fast mode, injected clock, a
// recording output): the car is held until go whatever its controls, the
// race's events come out as "race: {json}" reasons, the lap event's time
// agrees with the crossings the published states show, and a respawn puts
// the car upright and at rest 2 m past its last gate at once.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "session/fakes.hpp"
#include "session/race_bots.hpp"
#include "stepping/resimulate.hpp"
#include "session/session.hpp"

namespace groundsim::session::test {
namespace {

// the sprint of tests/web/data/race, its sedan on a throttle table from t = 0
const char* kSprint = R"({"name": "sprint", "duration": 20, "output_rate": 50, "physics": {"dt": 0.004},
  "contact": {"friction": 1.0}, "ground": {"type": "plane"},
  "vehicle": {"name": "sedan", "kind": "road_car", "controls": [{"t": 0, "throttle": 0.7}]},
  "race": {"laps": 1, "circuit": false, "countdown": 3,
           "gates": [{"center": [10, 0], "width": 10, "heading_deg": 0}, {"center": [40, 0], "width": 10, "heading_deg": 0},
                     {"center": [70, 0], "width": 10, "heading_deg": 0}],
           "grid": [{"position": [0, 0], "heading_deg": 0}]}})";

struct RaceRig {
  // a session of `doc` (the sprint by default) stepped by hand
  explicit RaceRig(const std::string& doc = kSprint, std::vector<std::string> names = {"sedan"},
                   Mode mode = Mode::Fast, const std::string& id = "0000RACE") {
    const scenario::Scenario sc = scenario::parseScenario(doc);
    scenario::Scene scene = scenario::buildScene(sc);
    SessionSetup setup;
    setup.id = id;
    setup.token = "t";
    setup.scenario_json = doc;
    setup.vehicle_names = std::move(names);
    setup.duration = 20;
    setup.mode = mode;
    setup.publish_rate = 50;
    setup.control_tables = scene.control_tables;
    session = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, out, clock.now(), clock);
  }
  std::vector<nlohmann::json> race(const std::string& type = "") const {
    std::vector<nlohmann::json> v;
    for (const Event& e : out.events)
      if (e.reason.rfind("race: ", 0) == 0) {
        nlohmann::json j = nlohmann::json::parse(e.reason.substr(6));
        if (type.empty() || j["type"] == type) v.push_back(j);
      }
    return v;
  }
  ServiceConfig cfg;
  ManualClock clock;
  RecordingOutput out;
  std::shared_ptr<Session> session;
};

// A respawn of vehicle v: OP_RESET with steps = -1 - v.
Request respawnRequest(int v, std::int64_t id) {
  Request r;
  r.op = Op::Reset;
  r.steps = -1 - v;
  r.request_id = id;
  return r;
}

// when the published states put the car's centre across x (interpolated)
double crossing(const std::vector<Frame>& frames, double x) {
  for (size_t i = 1; i < frames.size(); ++i) {
    const double xa = frames[i - 1].vehicles[0].position.x(), xb = frames[i].vehicles[0].position.x();
    if (xa < x && xb >= x) return frames[i - 1].t + (frames[i].t - frames[i - 1].t) * (x - xa) / (xb - xa);
  }
  return NAN;
}

TEST(RaceSession, HeldUntilGoThenTimedAndRespawned) {
  RaceRig rig;
  // fast: to the duration, the clock moved on between runs (the publish budget)
  for (int i = 0; i < 10000 && (rig.out.frames.empty() || rig.out.frames.back().status != Status::Finished); ++i) {
    rig.session->run(rig.clock.now());
    rig.clock.advance(0.5);
  }
  const auto& frames = rig.out.frames;
  ASSERT_EQ(frames.back().status, Status::Finished);
  ASSERT_GT(frames.size(), 900u);
  // held: the throttle table says 0.7 from t = 0, the car stays on its slot until go
  double creep = 0.0;
  for (const Frame& f : frames)
    if (f.t < 3.0) creep = std::max(creep, std::abs(f.vehicles[0].position.x()));
  EXPECT_LT(creep, 0.05);
  EXPECT_GT(frames.back().vehicles[0].position.x(), 70.0);

  const auto layout = rig.race("race");
  ASSERT_EQ(layout.size(), 1u);
  EXPECT_EQ(layout[0]["gates"].size(), 3u);
  const auto go = rig.race("go");
  ASSERT_EQ(go.size(), 1u);
  EXPECT_EQ(go[0]["t"], 3.0);
  const auto start = rig.race("start"), gates = rig.race("gate"), laps = rig.race("lap"), fin = rig.race("finish");
  ASSERT_EQ(start.size(), 1u);
  ASSERT_EQ(gates.size(), 2u);
  ASSERT_EQ(laps.size(), 1u);
  ASSERT_EQ(fin.size(), 1u);
  EXPECT_EQ(fin[0]["position"], 1);
  const double dt = 0.004;
  // the server's crossing instants against the states' (published every 5 steps)
  const double t10 = crossing(frames, 10.0), t40 = crossing(frames, 40.0), t70 = crossing(frames, 70.0);
  EXPECT_NEAR(start[0]["t"].get<double>(), t10, dt);
  EXPECT_NEAR(gates[0]["split"].get<double>(), t40 - t10, dt);
  EXPECT_NEAR(laps[0]["lap_time"].get<double>(), t70 - t10, dt);
  EXPECT_NEAR(fin[0]["race_time"].get<double>(), t70 - 3.0, dt);
  std::printf("lap %.6f s; from the states %.6f s (difference %.2g s)\n", laps[0]["lap_time"].get<double>(), t70 - t10,
              laps[0]["lap_time"].get<double>() - (t70 - t10));
  EXPECT_FALSE(rig.race("standings").empty());

  // respawn (OP_RESET with steps = -1 - vehicle): the next frame has it 2 m past gate 2
  Request r;
  r.op = Op::Reset;
  r.steps = -1;
  r.request_id = 7;
  r.session_id = "0000RACE";
  r.token = "t";
  rig.session->post(r);
  const size_t before = frames.size();
  rig.clock.advance(0.5);
  rig.session->run(rig.clock.now());
  ASSERT_GT(rig.out.frames.size(), before);
  const VehicleSample& v = rig.out.frames.back().vehicles[0];
  EXPECT_NEAR(v.position.x(), 72.0, 1e-9);
  EXPECT_NEAR(v.position.y(), 0.0, 1e-9);
  EXPECT_LT(v.speed, 1e-9);
  const Vec3 up = v.orientation * Vec3::UnitZ();
  EXPECT_GT(up.z(), std::cos(0.02));  // upright
  ASSERT_EQ(rig.race("respawn").size(), 1u);
  EXPECT_EQ(rig.race("respawn")[0]["gate"], 2);
  bool replied = false;
  for (const Reply& rep : rig.out.replies) replied = replied || (rep.request_id == 7 && rep.ok);
  EXPECT_TRUE(replied);

  // a respawn of a vehicle the session does not have is refused
  r.steps = -5;
  r.request_id = 8;
  rig.session->post(r);
  rig.session->run(rig.clock.now());
  bool refused = false;
  for (const Reply& rep : rig.out.replies) refused = refused || (rep.request_id == 8 && !rep.ok);
  EXPECT_TRUE(refused);
}

// Two cars respawned at the same gate: the second is put along the gate's
// line, clear of the first (4 m between centres), 6 m to its left.
TEST(RaceSession, ASecondRespawnAtTheSameGateIsPutClearOfTheFirst) {
  const char* two = R"({"name": "two", "duration": 20, "output_rate": 50, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicles": [{"name": "a", "kind": "road_car", "controls": [{"t": 0, "throttle": 0.7}]},
                 {"name": "b", "kind": "road_car", "controls": [{"t": 0, "throttle": 0.7}]}],
    "race": {"laps": 1, "circuit": false, "countdown": 1,
             "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0}, {"center": [40, 0], "width": 14, "heading_deg": 0}],
             "grid": [{"position": [0, 2.5]}, {"position": [0, -2.5]}]}})";
  const scenario::Scenario sc = scenario::parseScenario(std::string(two));
  scenario::Scene scene = scenario::buildScene(sc);
  ServiceConfig cfg;
  ManualClock clock;
  RecordingOutput out;
  SessionSetup setup;
  setup.id = "0000TWO0";
  setup.token = "t";
  setup.scenario_json = two;
  setup.vehicle_names = {"a", "b"};
  setup.duration = 20;
  setup.mode = Mode::Fast;
  setup.publish_rate = 50;
  setup.control_tables = scene.control_tables;
  auto s = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, out, clock.now(), clock);
  for (int i = 0; i < 10000 && (out.frames.empty() || out.frames.back().status != Status::Finished); ++i) {
    s->run(clock.now());
    clock.advance(0.5);
  }
  ASSERT_EQ(out.frames.back().status, Status::Finished);
  int finished = 0;
  for (const Event& e : out.events) finished += e.reason.find("\"type\":\"finish\"") != std::string::npos;
  ASSERT_EQ(finished, 2);
  for (int v : {0, 1}) {
    s->post(respawnRequest(v, 10 + v));
    clock.advance(0.5);
    s->run(clock.now());
  }
  const Frame& f = out.frames.back();
  EXPECT_NEAR(f.vehicles[0].position.x(), 42.0, 1e-9);
  EXPECT_NEAR(f.vehicles[0].position.y(), 0.0, 1e-9);
  EXPECT_NEAR(f.vehicles[1].position.x(), 42.0, 1e-9);
  EXPECT_NEAR(f.vehicles[1].position.y(), 6.0, 1e-9);  // 0 and +-3 are within 4 m of car a
}

// Respawn protection: a car stopped by a wall just past gate 1 is respawned
// 2 m past the gate, facing the wall 3 m ahead; for respawn_protection (3 s)
// it passes through, and no hit is reported; a session stepped on (lockstep)
Request stepRequest(std::int64_t steps, std::int64_t id) {
  Request r;
  r.op = Op::Step;
  r.steps = steps;
  r.request_id = id;
  return r;
}

TEST(RaceSession, ARespawnedCarPassesThroughForItsProtection) {
  const char* walled = R"({"name": "walled", "duration": 60, "output_rate": 50, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicle": {"name": "sedan", "kind": "road_car", "controls": [{"t": 0, "throttle": 0.7}]},
    "objects": [{"name": "wall", "shape": "box", "size": [1, 20, 1], "position": [46, 0, 0]}],
    "race": {"laps": 1, "circuit": false, "countdown": 1,
             "gates": [{"center": [10, 0], "width": 10, "heading_deg": 0}, {"center": [40, 0], "width": 10, "heading_deg": 0},
                       {"center": [80, 0], "width": 10, "heading_deg": 0}],
             "grid": [{"position": [0, 0]}]}})";
  const scenario::Scenario sc = scenario::parseScenario(std::string(walled));
  scenario::Scene scene = scenario::buildScene(sc);
  ServiceConfig cfg;
  ManualClock clock;
  RecordingOutput out;
  SessionSetup setup;
  setup.id = "0000WALL";
  setup.token = "t";
  setup.scenario_json = walled;
  setup.vehicle_names = {"sedan"};
  setup.mode = Mode::Lockstep;
  setup.control_tables = scene.control_tables;
  auto s = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, out, clock.now(), clock);
  s->post(stepRequest(2500, 1));  // 10 s: through gate 1, into the wall
  s->run(clock.now());
  ASSERT_FALSE(out.frames.empty());
  const double stopped = out.frames.back().vehicles[0].position.x();
  int hits = 0;
  for (const Event& e : out.events) hits += e.reason.rfind("hit: ", 0) == 0;
  for (const Hit& h : out.frames.back().hits) hits += h.a >= 0;
  EXPECT_LT(stopped, 46.0);  // held by the wall
  EXPECT_GT(hits, 0);
  s->post(respawnRequest(0, 2));
  s->post(stepRequest(700, 3));  // 2.8 s of the 3 s protection
  s->run(clock.now());
  const Frame f = out.frames.back();  // a copy: more frames follow
  EXPECT_GT(f.vehicles[0].position.x(), 48.0) << "the protected car did not pass through the wall";
  EXPECT_TRUE(f.hits.empty());
  bool hit_after = false;
  bool respawned = false;
  for (const Event& e : out.events) {
    respawned = respawned || e.reason.find("\"type\":\"respawn\"") != std::string::npos;
    hit_after = hit_after || (respawned && e.reason.rfind("hit: ", 0) == 0);
  }
  EXPECT_TRUE(respawned);
  EXPECT_FALSE(hit_after);
  // after it: the scenario's model again (the car's group has its probes)
  s->post(stepRequest(100, 4));
  s->run(clock.now());
  const Model& m = *out.frames.back().model;
  bool probes = false;
  for (const CollisionGroup& g : m.groups) probes = probes || (g.vehicle == 0 && g.probe_end > g.probe_begin);
  EXPECT_TRUE(probes);
  std::printf("stopped by the wall at x = %.2f m; respawned, %.2f m after 2.8 s of protection\n", stopped,
              f.vehicles[0].position.x());
}

TEST(RaceSession, ASessionWithoutARaceRefusesRespawn) {
  const char* plain = R"({"name": "plain", "duration": 1, "physics": {"dt": 0.004}, "contact": {"friction": 1.0},
    "ground": {"type": "plane"}, "vehicle": {"name": "sedan", "kind": "road_car"}})";
  scenario::Scene scene = scenario::buildScene(scenario::parseScenario(std::string(plain)));
  ServiceConfig cfg;
  ManualClock clock;
  RecordingOutput out;
  SessionSetup setup;
  setup.id = "0000PLAN";
  setup.token = "t";
  setup.scenario_json = plain;
  setup.vehicle_names = {"sedan"};
  setup.mode = Mode::Fast;
  auto s = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, out, clock.now(), clock);
  s->post(respawnRequest(0, 3));
  s->run(clock.now());
  bool refused = false;
  for (const Reply& rep : out.replies) refused = refused || (rep.request_id == 3 && !rep.ok);
  EXPECT_TRUE(refused);
  for (const Event& e : out.events) EXPECT_EQ(e.reason.rfind("race: ", 0), std::string::npos) << e.reason;
}

}  // namespace
}  // namespace groundsim::session::test

namespace groundsim::session::test {
namespace {

// An owner session of a race document and the standby that takes it over
// from the owner's newest snapshot and the applied entries after it, both
// in real time on one manual clock.
struct FailoverRig {
  // `assets`: the files the document names, sent with it (a bot policy)
  FailoverRig(const char* doc, std::vector<std::string> names, double duration,
              std::shared_ptr<const scenario::AssetBytes> assets = nullptr)
      : scenario(scenario::parseScenario(nlohmann::json::parse(doc), scenario::Budget{},
                                         assets ? scenario::FileAccess::fromAssets(assets) : scenario::FileAccess::none())),
        scene(scenario::buildScene(scenario)) {
    if (scenario.race) setup.bot_policy = scenario.race->bot_policy_text;  // as the service does
    cfg.replica_interval = 0.2;  // a snapshot every 50 ticks
    setup.id = "0000FAIL";
    setup.token = "t";
    setup.scenario_json = doc;
    setup.vehicle_names = std::move(names);
    setup.duration = duration;
    setup.mode = Mode::Realtime;
    setup.publish_rate = 50;
    setup.control_tables = scene.control_tables;
    owner = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, owner_out, clock.now(), clock);
    owner->run(clock.now());
  }
  // the owner runs by 0.1 s until `done` (at most `runs` times)
  template <class Done>
  void runOwnerUntil(Done done, int runs = 600) {
    for (int i = 0; i < runs && !done(); ++i) {
      clock.advance(0.1);
      owner->run(clock.now());
    }
  }
  // the host is lost: a standby resumes from its newest snapshot, the
  // entries after it and its last state ("" or why not)
  std::string failOver() {
    const Replica* snap = nullptr;
    for (const Replica& r : owner_out.replicas)
      if (r.kind == Replica::Kind::Snapshot) snap = &r;
    if (!snap) return "no snapshot";
    if (snap->meta.find("\"race\"") == std::string::npos) return "the snapshot does not carry the race";
    std::vector<Applied> log;
    for (const Applied& a : owner_out.applied)
      if (a.seq >= snap->applied_seq) log.push_back(a);
    standby = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, standby_out, clock.now(),
                                        clock);
    standby->setEpoch(2);
    return standby->resume(*snap, log, owner_out.frames.back().tick);
  }
  // both run on by 0.1 s until `done` (the owner as if it had not been lost)
  template <class Done>
  void runBothUntil(Done done, int runs = 600) {
    for (int i = 0; i < runs && !done(); ++i) {
      clock.advance(0.1);
      owner->run(clock.now());
      standby->run(clock.now());
    }
  }
  scenario::Scenario scenario;
  scenario::Scene scene;
  ServiceConfig cfg;
  ManualClock clock;
  RecordingOutput owner_out, standby_out;
  SessionSetup setup;
  std::shared_ptr<Session> owner, standby;
};

// The race events of one type (of car `car`, or every car) an output published.
std::vector<nlohmann::json> raceEvents(const RecordingOutput& out, const std::string& type, int car = -1) {
  std::vector<nlohmann::json> v;
  for (const Event& e : out.events)
    if (e.reason.rfind("race: ", 0) == 0) {
      nlohmann::json j = nlohmann::json::parse(e.reason.substr(6));
      if (j["type"] == type && (car < 0 || j["car"] == car)) v.push_back(j);
    }
  return v;
}

// A race survives its host (issue: race state in a fleet): the owner's
// snapshot carries the race's progress, so a standby that resumes the
// session mid-lap (after both cars started and passed gate 1, before the
// finish) times every player's lap, best lap, finish and place exactly as
// the owner does from the same point. Without the progress in the snapshot
// the standby's race starts afresh: no car has started, and it times no lap.
TEST(RaceSession, ARaceResumedOnAStandbyKeepsEveryPlayersLaps) {
  const char* two = R"({"name": "two", "duration": 30, "output_rate": 50, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicles": [{"name": "a", "kind": "road_car", "controls": [{"t": 0, "throttle": 0.8}]},
                 {"name": "b", "kind": "road_car", "controls": [{"t": 0, "throttle": 0.6}]}],
    "race": {"laps": 1, "circuit": false, "countdown": 1,
             "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0}, {"center": [30, 0], "width": 14, "heading_deg": 0},
                       {"center": [80, 0], "width": 14, "heading_deg": 0}],
             "grid": [{"position": [0, 2.5]}, {"position": [0, -2.5]}]}})";
  FailoverRig rig(two, {"a", "b"}, 30);
  auto passed = [&](const std::string& type) { return raceEvents(rig.owner_out, type).size(); };
  // the owner runs until both cars passed gate 1 (mid-lap)
  rig.runOwnerUntil([&] { return passed("gate") >= 2; }, 400);
  ASSERT_EQ(passed("start"), 2u);
  ASSERT_EQ(passed("gate"), 2u);
  ASSERT_EQ(passed("finish"), 0u) << "the failover must come mid-lap";
  ASSERT_EQ(rig.failOver(), "");
  rig.runBothUntil([&] { return raceEvents(rig.standby_out, "finish").size() >= 2; }, 400);
  const RecordingOutput &owner_out = rig.owner_out, &standby_out = rig.standby_out;
  const auto laps = raceEvents(owner_out, "lap"), fin = raceEvents(owner_out, "finish");
  const auto slaps = raceEvents(standby_out, "lap"), sfin = raceEvents(standby_out, "finish");
  ASSERT_EQ(laps.size(), 2u);
  ASSERT_EQ(slaps.size(), 2u) << "the standby times both players' laps";
  ASSERT_EQ(sfin.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(slaps[k]["car"], laps[k]["car"]);
    EXPECT_EQ(slaps[k]["lap_time"].get<double>(), laps[k]["lap_time"].get<double>()) << "car " << laps[k]["car"];
    EXPECT_EQ(slaps[k]["best"], laps[k]["best"]);
    EXPECT_EQ(sfin[k]["car"], fin[k]["car"]);
    EXPECT_EQ(sfin[k]["race_time"].get<double>(), fin[k]["race_time"].get<double>());
    EXPECT_EQ(sfin[k]["position"], fin[k]["position"]);
  }
  std::printf("after the failover: car %d lap %.6f s, car %d lap %.6f s, as on the lost host\n",
              slaps[0]["car"].get<int>(), slaps[0]["lap_time"].get<double>(), slaps[1]["car"].get<int>(),
              slaps[1]["lap_time"].get<double>());
  // the standings the standby publishes carry the same best laps
  const auto st = raceEvents(standby_out, "standings"), ost = raceEvents(owner_out, "standings");
  ASSERT_FALSE(st.empty());
  ASSERT_FALSE(ost.empty());
  EXPECT_EQ(st.back()["cars"], ost.back()["cars"]);
}

}  // namespace
}  // namespace groundsim::session::test

namespace groundsim::session::test {
namespace {

// Bots (race.bots, server/session/race_bots.hpp): the last vehicle is driven
// by the classical driver through the players' path. It is held until go
// like everyone, starts, passes every gate and finishes the stage on its
// own; each of its commands is an applied entry of that vehicle, 50 a
// second; and a standby that resumes the session mid-race from a snapshot
// and the log after it (the bot's commands replayed as logged, then its own
// bot driving) times the bot's finish to the same bit as the owner.
TEST(RaceSession, ABotDrivesTheLastCarThroughThePlayersPath) {
  const char* doc = R"({"name": "bots", "duration": 40, "output_rate": 50, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicles": [{"name": "player", "kind": "road_car"}, {"name": "bot", "kind": "road_car"}],
    "race": {"laps": 1, "circuit": false, "countdown": 1, "bots": 1,
             "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0}, {"center": [60, 10], "width": 14, "heading_deg": 30},
                       {"center": [120, 30], "width": 14, "heading_deg": 0}, {"center": [180, 20], "width": 14, "heading_deg": -20}],
             "grid": [{"position": [0, 2.5]}, {"position": [0, -2.5]}]}})";
  ASSERT_EQ(scenario::parseScenario(std::string(doc)).race->bots, 1);
  FailoverRig rig(doc, {"player", "bot"}, 40);
  // the owner runs until the bot passed its first gate after the start
  rig.runOwnerUntil([&] { return !raceEvents(rig.owner_out, "gate", 1).empty(); });
  ASSERT_EQ(raceEvents(rig.owner_out, "start", 1).size(), 1u) << "the bot never crossed the start line";
  ASSERT_EQ(raceEvents(rig.owner_out, "finish", 1).size(), 0u);
  // held until go (t = 1 s): the bot's car stays on its slot
  double creep = 0.0;
  for (const Frame& f : rig.owner_out.frames)
    if (f.t < 1.0) creep = std::max(creep, std::abs(f.vehicles[1].position.x()));
  EXPECT_LT(creep, 0.05);
  // its commands are the applied entries of vehicle 1, one each 20 ms
  int bot_entries = 0, player_entries = 0;
  for (const Applied& a : rig.owner_out.applied)
    if (a.kind == AppliedKind::Controls) (a.vehicle == 1 ? bot_entries : player_entries)++;
  EXPECT_EQ(player_entries, 0);
  EXPECT_NEAR(bot_entries, rig.owner_out.frames.back().t / 0.02, 2.0);
  // a standby takes over
  ASSERT_EQ(rig.failOver(), "");
  rig.runBothUntil([&] { return !raceEvents(rig.standby_out, "finish", 1).empty(); });
  const RecordingOutput &owner_out = rig.owner_out, &standby_out = rig.standby_out;
  const auto fin = raceEvents(owner_out, "finish", 1), sfin = raceEvents(standby_out, "finish", 1);
  ASSERT_EQ(fin.size(), 1u) << "the bot did not finish the stage";
  ASSERT_EQ(sfin.size(), 1u);
  EXPECT_EQ(sfin[0]["race_time"].get<double>(), fin[0]["race_time"].get<double>());
  std::printf("the bot finished the stage in %.6f s (on the standby: %.6f s); %d commands logged by then\n",
              fin[0]["race_time"].get<double>(), sfin[0]["race_time"].get<double>(), bot_entries);
}

// A trained driver at the wheel (race.bot_policy): the policy file travels
// with the scenario as an asset, the bot senses its car as the task did
// and drives through the players' path. The policy here is written down,
// not trained: one linear layer steering towards the track's point 10 m
// ahead (steer = 0.15 y of that point in the body frame, throttle half,
// no brake) -- pure pursuit in the policy file's own terms. It finishes
// the stage, acting every 40 ms (its control period of 10 steps of 4 ms),
// and a standby resumes it to the same bit.
TEST(RaceSession, ATrainedBotsPolicyFileDrivesThroughThePlayersPath) {
  const nlohmann::json policy = {
      {"format", "groundsim.policy"}, {"version", 1}, {"task", "pursuit"}, {"observation", {"track_ahead"}},
      {"track_ahead", {10.0}}, {"control_period", 10}, {"dt", 0.004},
      {"normalise", {{"mean", {0.0, 0.0}}, {"var", {1.0, 1.0}}, {"clip", 100.0}}},
      {"layers", {{{"weight", {{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.15}}}, {"bias", {0.0, -1.0, 0.0}}, {"activation", "none"}}}},
      {"action_low", {0.0, 0.0, -1.0}}, {"action_high", {1.0, 1.0, 1.0}}};
  auto assets = std::make_shared<scenario::AssetBytes>();
  (*assets)["pursuit.json"] = std::make_shared<const std::string>(policy.dump());
  const char* doc = R"({"name": "trained bots", "duration": 60, "output_rate": 50, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicles": [{"name": "player", "kind": "road_car"}, {"name": "bot", "kind": "road_car"}],
    "race": {"laps": 1, "circuit": false, "countdown": 1, "bots": 1, "bot_policy": "pursuit.json",
             "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0}, {"center": [60, 10], "width": 14, "heading_deg": 30},
                       {"center": [120, 30], "width": 14, "heading_deg": 0}, {"center": [180, 20], "width": 14, "heading_deg": -20}],
             "grid": [{"position": [0, 2.5]}, {"position": [0, -2.5]}]}})";
  FailoverRig rig(doc, {"player", "bot"}, 60, assets);
  ASSERT_TRUE(rig.setup.bot_policy);
  rig.runOwnerUntil([&] { return !raceEvents(rig.owner_out, "gate", 1).empty(); });
  ASSERT_EQ(raceEvents(rig.owner_out, "start", 1).size(), 1u) << "the bot never crossed the start line";
  int bot_entries = 0;
  for (const Applied& a : rig.owner_out.applied)
    if (a.kind == AppliedKind::Controls && a.vehicle == 1) ++bot_entries;
  EXPECT_NEAR(bot_entries, rig.owner_out.frames.back().t / 0.04, 2.0);
  ASSERT_EQ(rig.failOver(), "");
  rig.runBothUntil([&] { return !raceEvents(rig.standby_out, "finish", 1).empty(); });
  const auto fin = raceEvents(rig.owner_out, "finish", 1), sfin = raceEvents(rig.standby_out, "finish", 1);
  ASSERT_EQ(fin.size(), 1u) << "the trained bot did not finish the stage";
  ASSERT_EQ(sfin.size(), 1u);
  EXPECT_EQ(sfin[0]["race_time"].get<double>(), fin[0]["race_time"].get<double>());
  std::printf("the policy bot finished the stage in %.6f s (on the standby: %.6f s)\n",
              fin[0]["race_time"].get<double>(), sfin[0]["race_time"].get<double>());
}

// A protection lasts until the car is clear of the others: a car respawned
// behind a car standing on its line drives into it as a ghost and is still
// inside it when its 3 s are up; it stays a ghost until no other car's
// centre is within 5 m ahead or behind and 2.4 m aside, so the two never
// touch (a protection ending inside another car would meet a penalty
// force of metres of penetration).
TEST(RaceSession, AProtectionLastsUntilTheCarIsClearOfTheOthers) {
  const char* doc = R"({"name": "parked", "duration": 60, "output_rate": 50, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicles": [{"name": "a", "kind": "road_car", "controls": [{"t": 0, "throttle": 0.7}, {"t": 8.1, "throttle": 0.7}]},
                 {"name": "parked", "kind": "road_car", "controls": [{"t": 0, "brake": 1.0}]}],
    "race": {"laps": 1, "circuit": false, "countdown": 1,
             "gates": [{"center": [10, 0], "width": 10, "heading_deg": 0}, {"center": [30, 0], "width": 10, "heading_deg": 0},
                       {"center": [120, 0], "width": 10, "heading_deg": 0}],
             "grid": [{"position": [0, 0]}, {"position": [PARKED, 0]}]}})";
  std::string text(doc);  // the parked car 6 m past where a respawns (2 m past gate 1): clear of it, not of where a is 3 s later
  text.replace(text.find("PARKED"), 6, "38");
  RaceRig rig(text, {"a", "parked"}, Mode::Lockstep, "0000PARK");
  Session* s = rig.session.get();
  RecordingOutput& out = rig.out;
  ManualClock& clock = rig.clock;
  s->post(stepRequest(2000, 1));  // 8 s: past gate 1, into the parked car
  s->run(clock.now());
  ASSERT_EQ(raceEvents(out, "gate", 0).size(), 1u) << "car a did not pass gate 1";
  s->post(respawnRequest(0, 2));
  s->run(clock.now());
  const auto respawn = raceEvents(out, "respawn", 0);
  ASSERT_EQ(respawn.size(), 1u);
  const double t_respawn = respawn[0]["t"].get<double>();
  const size_t first = out.frames.size();
  for (int k = 0; k < 500; ++k) {  // 10 s more, a frame each 20 ms
    s->post(stepRequest(5, 3 + k));
    s->run(clock.now());
  }
  auto probes = [](const Frame& f) {
    for (const CollisionGroup& g : f.model->groups)
      if (g.vehicle == 0 && g.probe_end > g.probe_begin) return true;
    return false;
  };
  double gap_at_3s = 1e9, ended = -1.0, gap_at_end = 0.0;
  for (size_t i = first; i < out.frames.size(); ++i) {
    const Frame& f = out.frames[i];
    const double gap = f.vehicles[1].position.x() - f.vehicles[0].position.x();
    if (gap_at_3s > 1e8 && f.t >= t_respawn + 3.0) gap_at_3s = gap;
    if (ended < 0.0 && probes(f)) ended = f.t, gap_at_end = gap;
  }
  int touches = 0;
  for (size_t i = first; i < out.frames.size(); ++i)
    for (const Hit& h : out.frames[i].hits) touches += h.begin > t_respawn;  // the crash before it is not one
  std::printf("respawned at %.2f s; 3 s later %.2f m behind the parked car's centre; protection ended at %.2f s, "
              "%.2f m past it; %d touches\n", t_respawn, gap_at_3s, ended, -gap_at_end, touches);
  EXPECT_LT(std::abs(gap_at_3s), 5.0) << "the scene does not test anything: the car is clear when its 3 s are up";
  ASSERT_GT(ended, t_respawn + 3.0) << "the protection never ended";
  EXPECT_GE(std::abs(gap_at_end), 5.0) << "the protection ended with the car inside the other";
  EXPECT_LT(ended, t_respawn + 3.0 + 3.0) << "the protection went on long after the car was clear";
  EXPECT_EQ(touches, 0);
}

// A bot whose car is lost respawns as a player presses R (RaceBots::lost):
// here a wall stands across the stage after the start, so the classical
// bot drives into it and stays there, pushing. Once it has stood still
// for kStuckFor it is put back after its last gate, with its protection,
// through the same path as a player's respawn: a race event of its car and
// an applied entry of that vehicle, so the race re-simulates from the log
// to the same bit. The player's car, idle on the grid all along, is never
// respawned: only bots are put back by the server.
TEST(RaceSession, ABotStuckAgainstAWallRespawnsAsAPlayerWould) {
  const char* doc = R"({"name": "wall", "duration": 40, "output_rate": 50, "physics": {"dt": 0.004},
    "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "objects": [{"name": "wall", "shape": "box", "size": [1, 40, 2], "position": [45, 0, 0]}],
    "vehicles": [{"name": "player", "kind": "road_car"}, {"name": "bot", "kind": "road_car"}],
    "race": {"laps": 1, "circuit": false, "countdown": 1, "bots": 1,
             "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0}, {"center": [80, 0], "width": 14, "heading_deg": 0}],
             "grid": [{"position": [0, 2.5]}, {"position": [0, -2.5]}]}})";
  FailoverRig rig(doc, {"player", "bot"}, 40);
  rig.runOwnerUntil([&] { return raceEvents(rig.owner_out, "respawn").size() >= 2; }, 400);
  const auto respawns = raceEvents(rig.owner_out, "respawn");
  ASSERT_GE(respawns.size(), 2u) << "the bot stuck against the wall was never put back";
  for (const auto& e : respawns) EXPECT_EQ(e["car"], 1) << "only the bot is respawned by the server";
  // it stood still for kStuckFor first: against the wall, after go and the drive there
  const double first = respawns[0]["t"].get<double>();
  EXPECT_GT(first, 1.0 + RaceBots::kStuckFor);
  double last_moving = 0.0;  // the bot's car last faster than kStuckSpeed before the first respawn
  for (size_t i = 1; i < rig.owner_out.frames.size(); ++i) {
    const Frame &a = rig.owner_out.frames[i - 1], &b = rig.owner_out.frames[i];
    if (b.t > first - 1e-9) break;
    const double v = (b.vehicles[1].position - a.vehicles[1].position).norm() / (b.t - a.t);
    if (v > 1.5 * RaceBots::kStuckSpeed) last_moving = b.t;
  }
  EXPECT_GE(first - last_moving, RaceBots::kStuckFor - 0.1) << "respawned before it had stood still for long";
  EXPECT_LT(first - last_moving, RaceBots::kStuckFor + 1.0) << "left standing long after it was stuck";
  // a player's respawn entry, of vehicle 1
  int entries = 0;
  for (const Applied& a : rig.owner_out.applied)
    if (a.kind == AppliedKind::Respawn) {
      EXPECT_EQ(a.vehicle, 1);
      ++entries;
    }
  EXPECT_EQ(entries, static_cast<int>(respawns.size()));
  // the log re-simulates to the owner's last state, bit for bit
  Resimulator re(doc, scenario::FileAccess::none());
  for (const Applied& a : rig.owner_out.applied) ASSERT_EQ(re.apply(a), "");
  const Frame& last = rig.owner_out.frames.back();
  ASSERT_EQ(re.stepTo(last.tick), "");
  const Frame got = re.frame();
  for (size_t v = 0; v < 2; ++v) EXPECT_EQ(got.vehicles[v].position, last.vehicles[v].position) << "vehicle " << v;
  std::printf("the bot was put back at %.3f s (still since %.3f s), %zu respawns by %.2f s; re-simulated to the bit\n",
              first, last_moving, respawns.size(), last.t);
}

// A policy file a bot cannot drive with is refused when the session is
// made, at /race/bot_policy, naming what is wrong.
TEST(RaceSession, APolicyFileABotCannotUseIsRefusedAtItsField) {
  auto assets = std::make_shared<scenario::AssetBytes>();
  (*assets)["bad.json"] = std::make_shared<const std::string>(R"({"format": "groundsim.policy", "version": 1})");
  const char* doc = R"({"name": "bad bots", "duration": 5, "physics": {"dt": 0.004}, "ground": {"type": "plane"},
    "vehicles": [{"name": "player", "kind": "road_car"}, {"name": "bot", "kind": "road_car"}],
    "race": {"bots": 1, "bot_policy": "bad.json",
             "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0}, {"center": [60, 0], "width": 14, "heading_deg": 0}],
             "grid": [{"position": [0, 2.5]}, {"position": [0, -2.5]}]}})";
  try {
    FailoverRig rig(doc, {"player", "bot"}, 5, assets);
    FAIL() << "a session was made with a policy file that has no layers";
  } catch (const scenario::ScenarioError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/race/bot_policy"), std::string::npos) << what;
    EXPECT_NE(what.find("task: missing"), std::string::npos) << what;
    std::printf("refused: %s\n", what.c_str());
  }
  // and a policy named but not sent: refused when the scenario is read
  try {
    FailoverRig rig(doc, {"player", "bot"}, 5, std::make_shared<scenario::AssetBytes>());
    FAIL() << "a policy file that was not sent was accepted";
  } catch (const scenario::ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("/race/bot_policy"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace groundsim::session::test
