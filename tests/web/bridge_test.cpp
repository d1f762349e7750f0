// The bridge's pure parts: browser message validation, the controls
// mapping, ground grids against the grounds' closed forms, the car layout
// of the report's figure 1, and the state re-encoding.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/temp_dir.hpp"
#include "bridge/browser_limits.hpp"
#include "bridge/browser_message.hpp"
#include "bridge/controls.hpp"
#include "bridge/scene_view.hpp"
#include "bridge/shipped_scenarios.hpp"
#include "bridge/state_json.hpp"
#include "scenario/scenario.hpp"

using namespace groundsim::web;
using nlohmann::json;

namespace {

MessageError refusal(const std::string& text) {
  ParsedMessage m = parseBrowserMessage(text);
  EXPECT_FALSE(m.message) << text;
  return m.error;
}

std::string scenarioWithGround(const std::string& ground) {
  return R"({"name": "t", "duration": 1, "ground": )" + ground +
         R"(, "vehicle": {"name": "car", "initial": {"position": [0, 0, 0]}}})";
}

using groundsim::test::processTempDir;

}  // namespace

TEST(BrowserMessage, ControlsAreReadWithTheirValues) {
  ParsedMessage m = parseBrowserMessage(R"({"op":"controls","throttle":0.5,"brake":0,"steer":-1,"handbrake":true,"gear":-1})");
  ASSERT_TRUE(m.message);
  const auto& c = std::get<ControlsMsg>(*m.message).controls;
  EXPECT_EQ(c.throttle, 0.5);
  EXPECT_EQ(c.steer, -1);
  EXPECT_TRUE(c.handbrake);
  EXPECT_EQ(c.gear, -1);
}

TEST(BrowserMessage, RefusalsNameTheField) {
  EXPECT_EQ(refusal(R"({"op":"controls","throttle":1.5})").field, "/throttle");
  EXPECT_EQ(refusal(R"({"op":"controls","steer":"left"})").field, "/steer");
  EXPECT_EQ(refusal(R"({"op":"controls","gear":2})").field, "/gear");
  EXPECT_EQ(refusal(R"({"op":"controls","gear":1.5})").field, "/gear");
  EXPECT_EQ(refusal(R"({"op":"controls","turbo":1})").field, "/turbo");
  EXPECT_EQ(refusal(R"({"op":"join","session":"abcdef12"})").field, "/session");
  EXPECT_EQ(refusal(R"({"op":"join","session":"ABCDEF12","role":"admin"})").field, "/role");
  EXPECT_EQ(refusal(R"({"op":"create","config":"../../etc/passwd.json"})").field, "/config");
  EXPECT_EQ(refusal(R"({"op":"create","config":"plain.json","vehicles":100})").field, "/vehicles");
  EXPECT_EQ(refusal(R"({"op":"create","config":"race/circuit.json","bots":8})").field, "/bots");
  EXPECT_EQ(refusal(R"({"op":"create","config":"race/circuit.json","bots":-2})").field, "/bots");
  EXPECT_EQ(refusal(R"({"op":"create","config":"race/circuit.json","bot_skill":0.1})").field, "/bot_skill");
  EXPECT_EQ(refusal(R"({"op":"create","config":"race/circuit.json","bot_skill":2})").field, "/bot_skill");
  EXPECT_EQ(refusal(R"({"op":"ground","cx":0})").field, "/cy");
  EXPECT_EQ(refusal(R"({"op":"warp"})").field, "/op");
  EXPECT_EQ(refusal(R"({"op":null})").field, "/op");
  EXPECT_EQ(refusal(R"({"throttle":1})").field, "/op");
}

TEST(BrowserMessage, CreateNamesAScenarioByItsPathUnderConfigs) {
  for (const char* ok : {"plain.json", "tasks/goal.json", "a/b/c-d_e.1.json"}) {
    ParsedMessage m = parseBrowserMessage(std::string(R"({"op":"create","config":")") + ok + "\"}");
    ASSERT_TRUE(m.message) << ok << ": " << m.error.reason;
    EXPECT_EQ(std::get<CreateMsg>(*m.message).config, ok);
  }
  for (const char* bad : {"/etc/x.json", "../x.json", "tasks/../x.json", "./x.json", "a//b.json", "tasks/",
                          "a\\b.json", "a b.json", "x.jso", ".json", "tasks/goal.json/"})
    EXPECT_EQ(refusal(std::string(R"({"op":"create","config":")") + bad + "\"}").field, "/config") << bad;
  EXPECT_FALSE(validConfigId(std::string(124, 'a') + ".json"));
  EXPECT_TRUE(validConfigId(std::string(123, 'a') + ".json"));
}

TEST(BrowserMessage, TextSizeAndDepthAreBounded) {
  EXPECT_NE(refusal(std::string(kMaxMessageBytes + 1, ' ')).reason.find("exceeds the limit"), std::string::npos);
  std::string deep = R"({"op":"ping","t":)" + std::string(kMaxMessageDepth + 1, '[') + std::string(kMaxMessageDepth + 1, ']') + "}";
  EXPECT_NE(refusal(deep).reason.find("nested deeper"), std::string::npos);
  EXPECT_EQ(refusal("{\"op\":").reason, "not valid JSON");
  EXPECT_EQ(refusal("[]").field, "");
  // at the depth limit it parses (the field is still refused, for its type)
  std::string ok = R"({"op":"ping","t":)" + std::string(kMaxMessageDepth - 1, '[') + std::string(kMaxMessageDepth - 1, ']') + "}";
  EXPECT_EQ(refusal(ok).field, "/t");
}

TEST(Controls, MapToPerWheelTorquesAndFrontSteering) {
  ControlScale k;
  const auto d = toDrive(Controls{1.0, 0.0, 0.5, false, 1}, 2, 4, k);
  EXPECT_EQ(d.vehicle, 2);
  EXPECT_EQ(d.nwheels, 4);
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(d.drive_torque[i], k.drive_torque);
  EXPECT_DOUBLE_EQ(d.steer[0], 0.5 * k.steer);
  EXPECT_DOUBLE_EQ(d.steer[1], 0.5 * k.steer);
  EXPECT_EQ(d.steer[2], 0.0);
  const auto r = toDrive(Controls{0.5, 0.0, 0.0, true, -1}, 0, 4, k);
  EXPECT_DOUBLE_EQ(r.drive_torque[0], -0.5 * k.drive_torque);
  EXPECT_EQ(r.brake_torque[0], 0.0);  // the handbrake holds the rear wheels only
  EXPECT_DOUBLE_EQ(r.brake_torque[3], k.brake_torque);
  const auto n = toDrive(Controls{1.0, 0.0, 0.0, false, 0}, 0, 4, k);
  EXPECT_EQ(n.drive_torque[0], 0.0);  // neutral
}

TEST(GroundGrid, CosineWaveMatchesItsClosedForm) {
  auto view = makeSceneView(scenarioWithGround(R"({"type":"cosine","amplitude":0.5,"wavelength":6.283185307179586})"));
  const json g = groundGrid(*view->ground, 3.0, 1.0, 21, 0.5);
  const int n = g["n"];
  ASSERT_EQ(n, 21);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = g["x0"].get<double>() + j * 0.5;
      EXPECT_NEAR(g["z"][i * n + j].get<double>(), 0.5 * std::cos(x), 6e-4) << x;  // rounded to mm
    }
  EXPECT_NEAR(g["x0"].get<double>(), 3.0 - 5.0, 1e-12);
}

TEST(GroundGrid, InclineAndExpressionMatchTheirClosedForms) {
  auto incline = makeSceneView(scenarioWithGround(R"({"type":"incline","angle_deg":30,"downhill":[1,0]})"));
  const json a = groundGrid(*incline->ground, 0, 0, 11, 1.0);
  for (int j = 0; j < 11; ++j) {
    const double x = a["x0"].get<double>() + j;
    EXPECT_NEAR(a["z"][j].get<double>(), -std::tan(std::numbers::pi / 6) * x, 6e-4);
  }
  auto expr = makeSceneView(scenarioWithGround(R"j({"type":"expression","expression":"z + 0.15*x - 0.05*cos(3*x)","gradient_bound":1.05})j"));
  const json e = groundGrid(*expr->ground, 0, 0, 11, 0.7);
  for (int j = 0; j < 11; ++j) {
    const double x = e["x0"].get<double>() + j * 0.7;
    EXPECT_NEAR(e["z"][5 * 11 + j].get<double>(), -0.15 * x + 0.05 * std::cos(3 * x), 6e-4);
  }
}

TEST(GroundGrid, HeightIsFoundFromAFarStart) {
  auto view = makeSceneView(scenarioWithGround(R"({"type":"plane"})"));
  double z = 0;
  EXPECT_TRUE(surfaceHeight(*view->ground, 5, 5, 3.0, &z));
  EXPECT_NEAR(z, 0.0, 1e-9);
}

TEST(Layout, ReportCarHasFigureOnePointsAndSprings) {
  auto view = makeSceneView(scenarioWithGround(R"({"type":"plane"})"));
  const json& v = view->layout["vehicles"][0];
  ASSERT_EQ(v["wheels"].size(), 4u);
  EXPECT_EQ(view->wheels[0], 4);
  // 8 axle points + 4 rims of 20, each rim point tied to its corner's 2 axle points
  EXPECT_EQ(v["points"].size(), 8u + 80u);
  EXPECT_EQ(v["springs"].size(), 160u);
  const double fx[] = {1.5, 1.5, -1.5, -1.5}, fy[] = {1, -1, 1, -1};
  for (int i = 0; i < 4; ++i) {
    const json& w = v["wheels"][i];
    EXPECT_NEAR(w["offset"][0].get<double>(), fx[i], 1e-9);
    EXPECT_NEAR(w["offset"][1].get<double>(), fy[i], 1e-9);
    EXPECT_EQ(w["steerable"].get<bool>(), i < 2);
    EXPECT_DOUBLE_EQ(w["radius"].get<double>(), 1.0);
    EXPECT_GT(w["radial_stiffness"].get<double>(), 0.0);
  }
  int rim = 0;
  for (const json& p : v["points"])
    if (p[0].get<int>() >= 0) {
      ++rim;
      EXPECT_NEAR(std::hypot(p[2].get<double>(), p[4].get<double>()), 1.0, 1e-9);  // on the rim, axle along y
    }
  EXPECT_EQ(rim, 80);
}

// A road car's wheels are its four struts' hubs (physics/road_car/road_car.hpp), not
// model wheels: the layout places them from the car's own geometry.
TEST(Layout, RoadCarWheelsSitOnItsAxlesAndTrack) {
  const double wheelbase = 2.7, a = 1.2, track = 1.55, r = 0.32;
  const std::string doc = R"({"ground":{"type":"plane"},"vehicle":{"kind":"road_car","name":"sedan",
    "initial":{"position":[0,0,0]}}})";
  auto view = makeSceneView(doc);
  const json& v = view->layout["vehicles"][0];
  ASSERT_EQ(v["wheels"].size(), 4u);
  EXPECT_EQ(view->wheels[0], 4);
  EXPECT_TRUE(view->road_car[0]);
  const double fx[] = {a, a, a - wheelbase, a - wheelbase}, fy[] = {track / 2, -track / 2, track / 2, -track / 2};
  for (int i = 0; i < 4; ++i) {
    const json& w = v["wheels"][i];
    EXPECT_NEAR(w["offset"][0].get<double>(), fx[i], 1e-9) << i;
    EXPECT_NEAR(w["offset"][1].get<double>(), fy[i], 1e-9) << i;
    EXPECT_LT(w["offset"][2].get<double>(), 0.0) << "hubs below the centre of mass";
    EXPECT_DOUBLE_EQ(w["radius"].get<double>(), r);
    EXPECT_EQ(w["steerable"].get<bool>(), i < 2);
    EXPECT_TRUE(w["strut"].get<bool>());
  }
  EXPECT_LT(v["body_min"][0].get<double>(), a - wheelbase);
  EXPECT_GT(v["body_max"][0].get<double>(), a);
}

TEST(Layout, CopiesOfACarMakeAValidScenario) {
  const std::string doc = withVehicles(scenarioWithGround(R"({"type":"plane"})"), 3, 1.0);
  auto view = makeSceneView(doc);
  EXPECT_EQ(view->layout["vehicles"].size(), 3u);
  EXPECT_EQ(view->layout["vehicles"][2]["name"], "car-3");
}

// A race with bots: the players' copies first, then one car per bot, which
// the session's drivers take (the last `bots` vehicles).
TEST(Layout, ARaceWithBotsGetsACarPerBotAfterThePlayers) {
  json doc = json::parse(scenarioWithGround(R"({"type":"plane"})"));
  json gates = json::array();
  gates.push_back({{"center", {10, 0}}, {"width", 10}, {"heading_deg", 0}});
  gates.push_back({{"center", {60, 0}}, {"width", 10}, {"heading_deg", 0}});
  doc["race"] = {{"bots", 1}, {"gates", gates}};
  const std::string two = withVehicles(doc.dump(), 2, 1.0);
  const groundsim::scenario::Scenario sc = groundsim::scenario::parseScenario(two);
  ASSERT_EQ(sc.vehicles.size(), 3u);
  EXPECT_EQ(sc.vehicles[1].name, "car-2");
  EXPECT_EQ(sc.vehicles[2].name, "ada-bot");
  EXPECT_EQ(sc.race->bots, 1);
}

// The lobby's bots choice (a create's "bots" and "bot_skill"): the race's
// own bots are replaced by as many as asked, named from the roster, the
// players kept; a scenario without a race is refused at /race.
TEST(Layout, TheLobbysBotsChoiceReplacesTheRacesBots) {
  json doc = json::parse(scenarioWithGround(R"({"type":"plane"})"));
  json gates = json::array();
  gates.push_back({{"center", {10, 0}}, {"width", 10}, {"heading_deg", 0}});
  gates.push_back({{"center", {60, 0}}, {"width", 10}, {"heading_deg", 0}});
  doc["race"] = {{"bots", 1}, {"gates", gates}};
  const std::string one_bot = withVehicles(doc.dump(), 1, 1.0);  // a player and a bot
  const groundsim::scenario::Scenario three =
      groundsim::scenario::parseScenario(withBots(one_bot, 3, 0.6));
  ASSERT_EQ(three.vehicles.size(), 4u);
  EXPECT_EQ(three.vehicles[0].name, "car-1");
  EXPECT_EQ(three.vehicles[1].name, "ada-bot");
  EXPECT_EQ(three.vehicles[3].name, "carla-bot");
  EXPECT_EQ(three.race->bots, 3);
  EXPECT_EQ(three.race->bot_skill, 0.6);
  const groundsim::scenario::Scenario none = groundsim::scenario::parseScenario(withBots(one_bot, 0, 0.0));
  EXPECT_EQ(none.vehicles.size(), 1u);
  EXPECT_EQ(none.race->bots, 0);
  try {
    withBots(scenarioWithGround(R"({"type":"plane"})"), 2, 0.0);
    FAIL() << "bots without a race were accepted";
  } catch (const groundsim::scenario::ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("/race"), std::string::npos) << e.what();
  }
}

TEST(ShippedScenarios, EveryConfigIsListedWithItsDescriptionAndCapacity) {
  namespace fs = std::filesystem;
  const ShippedList list = listShippedScenarios(GROUNDSIM_CONFIG_DIR, 1.0, kMaxCreateVehicles);
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(GROUNDSIM_CONFIG_DIR))
    if (e.path().extension() == ".json")
      files.push_back(e.path().lexically_relative(GROUNDSIM_CONFIG_DIR).generic_string());
  EXPECT_EQ(list.scenarios.size(), files.size());
  for (const std::string& s : list.skipped) ADD_FAILURE() << "not offered: " << s;
  std::map<std::string, ShippedScenario> by_id;
  for (const auto& s : list.scenarios) by_id[s.id] = s;
  for (const std::string& f : files) {
    ASSERT_TRUE(by_id.count(f)) << f;
    const ShippedScenario& s = by_id[f];
    std::ifstream in(fs::path(GROUNDSIM_CONFIG_DIR) / f);
    const json doc = json::parse(in);
    EXPECT_EQ(s.description, doc.value("description", "")) << f;
    EXPECT_EQ(s.name, doc.value("name", "")) << f;
    EXPECT_GE(s.min_cars, 1) << f;
    EXPECT_GE(s.max_cars, s.min_cars) << f;
    EXPECT_LE(s.max_cars, kMaxCreateVehicles) << f;
  }
  // the report's car on a plane: one per player, up to the create's limit
  EXPECT_EQ(by_id["plain.json"].min_cars, 1);
  EXPECT_EQ(by_id["plain.json"].max_cars, kMaxCreateVehicles);
  EXPECT_EQ(by_id["plain.json"].vehicles, 1);
  // the top level first, then the folders'
  EXPECT_EQ(list.scenarios.front().id.find('/'), std::string::npos);
  EXPECT_NE(list.scenarios.back().id.find('/'), std::string::npos);
  // the server's --max-vehicles bounds it too
  const ShippedList three = listShippedScenarios(GROUNDSIM_CONFIG_DIR, 1.0, 3);
  for (const auto& s : three.scenarios) EXPECT_LE(s.max_cars, 3) << s.id;
}

TEST(ShippedScenarios, ACarThatCannotBeCopiedHostsOnePlayerAndABrokenFileIsNotOffered) {
  namespace fs = std::filesystem;
  const fs::path dir = processTempDir() / "shipped";
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "plane.json") << scenarioWithGround(R"({"type":"plane"})");
  // a task naming its car: copies are renamed (car-1, car-2 ...), so it hosts only its own
  std::ofstream(dir / "sub" / "task.json")
      << R"({"name": "t", "description": "a task", "duration": 1, "ground": {"type": "plane"},)"
         R"( "vehicle": {"name": "car", "initial": {"position": [0, 0, 0]}},)"
         R"( "task": {"vehicle": "car", "observation": ["speed"], "action": {"type": "wheel_torques", "max_torque": 1.0}}})";
  std::ofstream(dir / "broken.json") << R"({"name": "b", "ground": {"type": "nowhere"}})";
  std::ofstream(dir / "notes.txt") << "not a scenario";
  const ShippedList list = listShippedScenarios(dir.string(), 1.0, 8);
  ASSERT_EQ(list.scenarios.size(), 2u);
  EXPECT_EQ(list.scenarios[0].id, "plane.json");
  EXPECT_EQ(list.scenarios[0].max_cars, 8);
  EXPECT_EQ(list.scenarios[1].id, "sub/task.json");
  EXPECT_EQ(list.scenarios[1].description, "a task");
  EXPECT_EQ(list.scenarios[1].min_cars, 1);
  EXPECT_EQ(list.scenarios[1].max_cars, 1) << list.scenarios[1].limit;
  ASSERT_EQ(list.skipped.size(), 1u);
  EXPECT_EQ(list.skipped[0].rfind("broken.json: ", 0), 0u) << list.skipped[0];
  fs::remove_all(dir);
}

TEST(ShippedScenarios, TheMostCarsWithinTheBudgetAreFoundByBisection) {
  namespace fs = std::filesystem;
  // a run long enough that 2 cars' work is within the budget (max_work) and 3 cars' is not
  json doc = json::parse(scenarioWithGround(R"({"type":"plane"})"));
  doc["physics"] = {{"integrator", "rk4"}};  // 4 evaluations a step: fewer steps than max_steps
  groundsim::scenario::Budget budget;
  const auto one = groundsim::scenario::parseScenario(doc.dump());
  const double steps_per_s = 1.0 / one.options.dt;
  const double work1 = groundsim::scenario::estimateModelSize(one).work_per_step;
  doc["duration"] = budget.max_work / (2.5 * work1 * steps_per_s);
  ASSERT_LT(doc["duration"].get<double>() * steps_per_s, budget.max_steps);
  const fs::path dir = processTempDir() / "budget";
  fs::create_directories(dir);
  std::ofstream(dir / "long.json") << doc.dump();
  const ShippedList list = listShippedScenarios(dir.string(), 1.0, 8);
  fs::remove_all(dir);
  ASSERT_EQ(list.scenarios.size(), 1u);
  EXPECT_EQ(list.scenarios[0].min_cars, 1);
  EXPECT_EQ(list.scenarios[0].max_cars, 2);
  EXPECT_EQ(list.scenarios[0].limit.rfind("3 cars refused: /duration", 0), 0u) << list.scenarios[0].limit;
}

TEST(StateJson, ReEncodesEveryField) {
  groundsim::state_t s{};
  s.session_id = "ABCDEF12";
  s.seq = 7;
  s.t = 1.25;
  s.status = 1;
  s.status_reason = "quote \" and \\ and \n";
  s.nvehicles = 1;
  s.vehicles.resize(1);
  auto& v = s.vehicles[0];
  v.name = "car";
  v.position[0] = 1.5;
  v.orientation[0] = 1;
  v.speed = 3.25;
  v.wheel_count = 4;
  v.wheel_spin[3] = -2;
  v.in_contact[1] = true;
  v.normal_force[2] = std::nan("");  // a foreign log: never NaN in the JSON
  const json j = json::parse(stateJson(s, 12.5));
  EXPECT_EQ(j["session"], "ABCDEF12");
  EXPECT_EQ(j["seq"], 7);
  EXPECT_EQ(j["t"], 1.25);
  EXPECT_EQ(j["wall"], 12.5);
  EXPECT_EQ(j["reason"], s.status_reason);
  EXPECT_EQ(j["vehicles"][0]["p"][0], 1.5);
  EXPECT_EQ(j["vehicles"][0]["speed"], 3.25);
  EXPECT_EQ(j["vehicles"][0]["spin"][3], -2);
  EXPECT_EQ(j["vehicles"][0]["contact"][1], true);
  EXPECT_EQ(j["vehicles"][0]["N"][2], 0);
}

TEST(StateJson, CarriesTheLiveErrorEstimate) {
  groundsim::state_t s{};
  s.session_id = "ABCDEF12";
  s.error_estimate = 0.0031;  // a session run to a tolerance
  EXPECT_DOUBLE_EQ(json::parse(stateJson(s, 1.0))["error_estimate"].get<double>(), 0.0031);
  s.error_estimate = -1;  // none: the page hides the line
  EXPECT_EQ(json::parse(stateJson(s, 1.0))["error_estimate"], -1);
}

// A player's name on create and join (printable, at most 24 bytes, kept
// for the lobby) and the lobby's preview op (a shipped scenario's id).
TEST(BrowserMessage, PlayerNameAndPreview) {
  using groundsim::web::parseBrowserMessage;
  auto ok = parseBrowserMessage(R"({"op":"join","session":"0123ABCD","role":"drive","player":"Ann Åberg"})");
  ASSERT_TRUE(ok.message.has_value()) << ok.error.field << ": " << ok.error.reason;
  EXPECT_EQ(std::get<groundsim::web::JoinMsg>(*ok.message).player, "Ann Åberg");
  ok = parseBrowserMessage(R"({"op":"create","config":"race/circuit.json","vehicles":2,"player":"Bob"})");
  ASSERT_TRUE(ok.message.has_value());
  EXPECT_EQ(std::get<groundsim::web::CreateMsg>(*ok.message).player, "Bob");
  auto bad = parseBrowserMessage(R"({"op":"join","session":"0123ABCD","player":"a\nb"})");
  EXPECT_EQ(bad.error.field, "/player");
  bad = parseBrowserMessage(R"({"op":"create","config":"plain.json","player":"0123456789012345678901234"})");
  EXPECT_EQ(bad.error.field, "/player");
  bad = parseBrowserMessage(R"({"op":"join","session":"0123ABCD","player":7})");
  EXPECT_EQ(bad.error.field, "/player");
  ok = parseBrowserMessage(R"({"op":"preview","config":"race/circuit.json"})");
  ASSERT_TRUE(ok.message.has_value());
  EXPECT_EQ(std::get<groundsim::web::PreviewMsg>(*ok.message).config, "race/circuit.json");
  EXPECT_EQ(parseBrowserMessage(R"({"op":"preview","config":"../etc/passwd"})").error.field, "/config");
  EXPECT_EQ(parseBrowserMessage(R"({"op":"preview"})").error.field, "/config");
}

// One browser's creates against groundsim-web's limits: each refusal names
// the field, the limit and its flag; the minute's budget refills with time
// (given instants: no wall clock).
TEST(BrowserLimits, ACreateIsHeldToEveryLimitNamingItsFlag) {
  BrowserLimits l;  // the defaults: realtime only, 8 cars, 60 Hz, 2 sessions, 20 creates a minute
  BrowserAllowance a(l);
  const auto t0 = TokenBucket::Clock::time_point{} + std::chrono::hours(1);
  auto no = a.create(l, "fast", 8, 1000, 0, t0);
  ASSERT_TRUE(no);
  EXPECT_EQ(no->field, "/mode");
  EXPECT_NE(no->reason.find("(realtime; groundsim-web --browser-modes)"), std::string::npos) << no->reason;
  no = a.create(l, "realtime", 9, 0, 0, t0);
  ASSERT_TRUE(no);
  EXPECT_EQ(no->field, "/vehicles");
  EXPECT_NE(no->reason.find("at most 8 in a browser's session (groundsim-web --browser-cars)"), std::string::npos);
  no = a.create(l, "realtime", 1, 1000, 0, t0);
  ASSERT_TRUE(no);
  EXPECT_EQ(no->field, "/publish_rate");
  EXPECT_NE(no->reason.find("1000 Hz, at most 60 (groundsim-web --browser-publish-rate)"), std::string::npos);
  no = a.create(l, "realtime", 1, 0, 2, t0);
  ASSERT_TRUE(no);
  EXPECT_NE(no->reason.find("owns 2 sessions, at most 2 at once (groundsim-web --browser-sessions)"), std::string::npos);
  // refusals above took nothing from the minute's 20
  for (int k = 0; k < 20; ++k) EXPECT_FALSE(a.create(l, "realtime", 1, 60, 0, t0)) << k;
  no = a.create(l, "realtime", 1, 60, 0, t0);
  ASSERT_TRUE(no);
  EXPECT_NE(no->reason.find("at most 20 a minute (groundsim-web --browser-creates); the next in 3 s"), std::string::npos)
      << no->reason;
  EXPECT_TRUE(a.create(l, "realtime", 1, 60, 0, t0 + std::chrono::milliseconds(2900)));
  EXPECT_FALSE(a.create(l, "realtime", 1, 60, 0, t0 + std::chrono::milliseconds(3100)));
  // what the operator allows
  BrowserLimits open = l;
  ASSERT_FALSE(parseModes("realtime,fast,lockstep", open.modes));
  EXPECT_EQ(joinModes(open.modes), "fast,lockstep,realtime");
  EXPECT_TRUE(parseModes("realtime,warp", open.modes));
  BrowserAllowance b(l);
  l.modes = {"realtime", "fast"};
  EXPECT_FALSE(b.create(l, "fast", 8, 60, 1, t0));
  // the publish rate asked of the server: the browser's, else the scenario's, held to the limit
  EXPECT_EQ(publishRateFor(l, 0, 50), 50);
  EXPECT_EQ(publishRateFor(l, 0, 500), 60);
  EXPECT_EQ(publishRateFor(l, 30, 500), 30);
}

TEST(BrowserLimits, MessagesArePacedNotDropped) {
  TokenBucket b(200, 200);
  const auto t0 = TokenBucket::Clock::time_point{} + std::chrono::hours(1);
  for (int k = 0; k < 200; ++k) EXPECT_EQ(b.take(t0), 0.0) << k;  // a second's burst
  const double wait = b.take(t0);
  EXPECT_NEAR(wait, 1.0 / 200, 1e-12);  // the next, once the rate allows
  EXPECT_EQ(b.take(t0 + std::chrono::microseconds(5001)), 0.0);
  TokenBucket none(0, 0);
  EXPECT_EQ(none.take(t0), 0.0) << "0: no limit";
}
