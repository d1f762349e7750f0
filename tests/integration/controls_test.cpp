// Normalized controls of a road car (controls_t on GROUNDSIM_CONTROLS) and
// its state (car_state_t on GROUNDSIM_CAR_STATE_<id>), end to end: the real
// groundsim-server, `groundsim drive` on configs/sedan.json in lockstep mode,
// over UDP multicast in this test's own network namespace (netns_run.sh).
// The verdicts are closed-form bounds on the sedan's motion, never timing.
#include <chrono>
#include <cmath>
#include <csignal>
#include <memory>
#include <sstream>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <groundsim/car_state_t.hpp>
#include <groundsim/event_t.hpp>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "process.hpp"
#include "test_env.hpp"

namespace groundsim::itest {
namespace {

const std::string kSedan = std::string(GROUNDSIM_CONFIG_DIR) + "/sedan.json";
constexpr double kG = 9.81, kMu = 1.0;  // sedan.json: contact.friction 1.0
constexpr int kStepsPerSecond = 250;    // sedan.json: physics.dt 0.004

// Speed from a `step --exact` line: tick t name status x y z qw qx qy qz vx vy vz ...
double speedOf(const std::string& out) {
  std::istringstream in(out.substr(0, out.find('\n')));
  std::string tok;
  double v[3] = {0, 0, 0};
  for (int i = 0; i <= 13 && in >> tok; ++i)
    if (i >= 11) v[i - 11] = std::stod(tok);
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// The newest car_state_t of one session, heard in this process.
class CarStateListener {
 public:
  explicit CarStateListener(const std::string& session) : lcm_(kUrl) {
    lcm_.subscribeFunction(net::carStateChannel(session), &CarStateListener::on, this);
  }
  bool waitForSeqAtLeast(long long seq, double timeout_s = 20) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < end) {
      if (have_ && latest_.seq >= seq) return true;
      lcm_.handleTimeout(50);
    }
    return false;
  }
  const groundsim::car_state_t& latest() const { return latest_; }

 private:
  static void on(const lcm::ReceiveBuffer* rbuf, const std::string&, CarStateListener* self) {
    if (net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), self->latest_, "car_state_t").ok())
      self->have_ = true;
  }
  lcm::LCM lcm_;
  groundsim::car_state_t latest_;
  bool have_ = false;
};

class Controls : public ::testing::Test {
 protected:
  void SetUp() override {
    token_file_ = tokenFile("controls");
    std::remove(token_file_.c_str());
    server_ = std::make_unique<Process>(
        std::vector<std::string>{kServer, "--lcm-url", kUrl, "--workers", "2", "--max-sessions", "4"});
    ASSERT_TRUE(server_->waitForOutput("groundsim-server ready", 20)) << server_->wait(1).err;
  }
  void TearDown() override {
    server_->signal(SIGTERM);
    server_->wait(30);
    std::remove(token_file_.c_str());
    std::remove((token_file_ + ".lock").c_str());
  }
  Result cli(std::vector<std::string> args, const std::string& stdin_text = "") {
    args.insert(args.begin(), kCli);
    args.insert(args.end(), {"--lcm-url", kUrl, "--token-file", token_file_});
    withReplyTimeout(args);
    return run(args, stdin_text, 60);
  }
  std::string create(const std::string& file) {
    const Result r = cli({"create", file, "--mode", "lockstep"});
    EXPECT_EQ(r.status, 0) << r.err;
    return lastLine(r.out);
  }
  // `groundsim drive ID --controls car --hold` with a script
  Result drive(const std::string& id, const std::string& script) {
    return cli({"drive", id, "--controls", "car", "--hold"}, script + "quit\n");
  }
  double stepSeconds(const std::string& id, double seconds) {
    const Result r = cli({"step", id, std::to_string(static_cast<long long>(seconds * kStepsPerSecond)), "--exact"});
    EXPECT_EQ(r.status, 0) << r.err;
    return speedOf(r.out);
  }

  std::unique_ptr<Process> server_;
  std::string token_file_;
};

TEST_F(Controls, ThrottleThenBrakeDriveTheSedan) {
  const std::string id = create(kSedan);
  CarStateListener cars(id);
  ASSERT_EQ(drive(id, "throttle 1\n").status, 0);
  const double launched = stepSeconds(id, 2.0);
  // from rest: faster, but never beyond what the tyres carry (mu g t)
  EXPECT_GT(launched, 3.0);
  EXPECT_LT(launched, kMu * kG * 2.0);
  ASSERT_TRUE(cars.waitForSeqAtLeast(0));
  {
    const groundsim::car_state_t& c = cars.latest();
    ASSERT_EQ(c.ncars, 1);
    EXPECT_EQ(c.cars[0].vehicle, 0);
    EXPECT_EQ(c.cars[0].throttle, 1.0);  // applied as commanded
    EXPECT_EQ(c.cars[0].brake, 0.0);
    EXPECT_GE(c.cars[0].gear, 1);
    EXPECT_GT(c.cars[0].engine_rpm, 900.0);  // above idle
    EXPECT_GT(c.cars[0].drive_power, 0.0);
    EXPECT_NEAR(c.cars[0].speed, launched, 1e-9);
  }

  ASSERT_EQ(drive(id, "throttle 0\nbrake 1\n").status, 0);
  const double braked = stepSeconds(id, 0.5);
  // full brakes take off at least half of mu g (ABS holds near the peak),
  // and no more than mu g
  EXPECT_LT(braked, std::max(0.0, launched - 0.5 * kMu * kG * 0.5) + 0.05) << launched;
  EXPECT_GT(braked, launched - 1.1 * kMu * kG * 0.5) << launched;
  ASSERT_TRUE(cars.waitForSeqAtLeast(1));
  EXPECT_EQ(cars.latest().cars[0].brake, 1.0);
  EXPECT_EQ(cars.latest().cars[0].throttle, 0.0);
}

TEST_F(Controls, BadValuesAreRefusedNamingTheField) {
  const std::string id = create(kSedan);
  // the session starts with the first row of sedan.json's controls table (throttle 1): release it
  ASSERT_EQ(drive(id, "release\n").status, 0);
  const Result nan = drive(id, "throttle nan\n");
  EXPECT_EQ(nan.status, 1);
  EXPECT_NE(nan.err.find("controls: throttle: nan is not finite"), std::string::npos) << nan.err;
  const Result brake = drive(id, "brake 1.5\n");
  EXPECT_EQ(brake.status, 1);
  EXPECT_NE(brake.err.find("controls: brake: 1.5 outside [0, 1]"), std::string::npos) << brake.err;
  const Result steer = drive(id, "steer -inf\n");
  EXPECT_EQ(steer.status, 1);
  EXPECT_NE(steer.err.find("controls: steer: -inf is not finite"), std::string::npos) << steer.err;
  const Result gear = drive(id, "gear 7\n");  // six gears
  EXPECT_EQ(gear.status, 1);
  EXPECT_NE(gear.err.find("controls: gear: 7 is not"), std::string::npos) << gear.err;
  const Result token = cli({"drive", id, "--controls", "car", "--token", "bad"}, "throttle 1\nquit\n");
  EXPECT_EQ(token.status, 1);
  EXPECT_NE(token.err.find("controls: wrong token"), std::string::npos) << token.err;
  // nothing refused reached the car: it is still at rest
  EXPECT_LT(stepSeconds(id, 1.0), 0.05);
}

TEST_F(Controls, RoadCarRefusesPerWheelTorques) {
  const std::string id = create(kSedan);
  const Result r = cli({"drive", id, "--controls", "wheels", "--hold"}, "throttle 1\nquit\n");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("drive: vehicle 0 is a road car"), std::string::npos) << r.err;
}

TEST_F(Controls, ReportCarRefusesRoadCarControls) {
  const std::string id = create(kPlain);
  const Result r = drive(id, "throttle 1\n");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("controls: vehicle: vehicle 0 is not a road car"), std::string::npos) << r.err;
  // and the report car keeps taking drive_t
  EXPECT_EQ(cli({"drive", id, "--controls", "wheels", "--hold"}, "throttle 1\nquit\n").status, 0);
}

}  // namespace
}  // namespace groundsim::itest
