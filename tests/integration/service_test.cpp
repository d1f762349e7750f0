// End-to-end tests of the network service: the real groundsim-server and
// real `groundsim` clients over UDP multicast. CTest runs each test in its
// own network namespace (netns_run.sh), so tests cannot hear each other.
// Pass/fail never depends on timing beyond generous timeouts.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <csignal>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <groundsim/event_t.hpp>
#include <groundsim/request_t.hpp>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "process.hpp"
#include "test_env.hpp"

namespace groundsim::itest {
namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// Reads one column of a `--exact` step line: tick t name status x y z qw qx qy qz vx vy vz ...
double field(const std::string& line, int index) {
  std::istringstream in(line);
  std::string tok;
  for (int i = 0; i <= index; ++i) in >> tok;
  return std::stod(tok);
}
constexpr int kX = 4, kVx = 11, kVy = 12;

// configs/sedan_slalom.json with an `accuracy` section, written to `file`.
void slalomWithAccuracy(const std::string& file, const std::string& accuracy) {
  std::ifstream in(std::string(GROUNDSIM_CONFIG_DIR) + "/sedan_slalom.json");
  std::stringstream text;
  text << in.rdbuf();
  std::string doc = text.str();
  doc.insert(doc.find('{') + 1, "\"accuracy\": " + accuracy + ", ");
  std::ofstream(file) << doc;
}

class Service : public ::testing::Test {
 protected:
  void SetUp() override {
    token_file_ = tokenFile("tokens");
    std::remove(token_file_.c_str());
    startServer();
  }
  void TearDown() override {
    stopServer();
    std::remove(token_file_.c_str());
    std::remove((token_file_ + ".lock").c_str());
  }

  void startServer() {
    server_ = std::make_unique<Process>(std::vector<std::string>{
        kServer, "--lcm-url", kUrl, "--workers", "2", "--max-sessions", "4", "--max-torque", "100"});
    ASSERT_TRUE(server_->waitForOutput("groundsim-server ready", 20)) << server_->wait(1).err;
  }
  Result stopServer() {
    if (!server_) return {};
    server_->signal(SIGTERM);
    Result r = server_->wait(30);
    server_.reset();
    return r;
  }

  // `groundsim ARGS... --lcm-url URL [--token-file F]`
  Result cli(std::vector<std::string> args, bool with_token, const std::string& stdin_text = "", double timeout = 60) {
    args.insert(args.begin(), kCli);
    args.insert(args.end(), {"--lcm-url", kUrl});
    if (with_token) args.insert(args.end(), {"--token-file", token_file_});
    withReplyTimeout(args);
    return run(args, stdin_text, timeout);
  }
  std::string create(std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"create", kPlain};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = cli(args, true);
    EXPECT_EQ(r.status, 0) << r.err;
    const std::string id = lastLine(r.out);
    EXPECT_EQ(id.size(), 8u) << r.out;
    return id;
  }
  Result step(const std::string& id, int n, int repeat = 1) {
    return cli({"step", id, std::to_string(n), "--repeat", std::to_string(repeat), "--exact"}, true);
  }

  std::unique_ptr<Process> server_;
  std::string token_file_;
};

TEST_F(Service, SeveralSessionsAtOnce) {
  const std::string a = create();
  const std::string b = create({"--mode", "fast", "--duration", "-1"});
  const std::string c = create({"--mode", "lockstep"});
  const Result list = cli({"list"}, false);
  ASSERT_EQ(list.status, 0) << list.err;
  for (const auto& id : {a, b, c}) EXPECT_NE(list.out.find(id), std::string::npos) << list.out;
  // the real time and the fast session both publish; the lockstep one answers steps
  for (const auto& id : {a, b}) {
    const Result w = cli({"watch", id, "--count", "3", "--duration", "30"}, false);
    EXPECT_EQ(w.status, 0) << w.err;
    EXPECT_EQ(lines(w.out).size(), 3u) << w.out;
  }
  const Result s = step(c, 100);
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_EQ(field(lines(s.out).at(0), 0), 100);  // tick
}

TEST_F(Service, SubscribersReceiveIdenticalStreams) {
  // lockstep publishes nothing until stepped: start the loggers, then let it run fast
  const std::string id = create({"--mode", "lockstep", "--duration", "1"});
  std::vector<std::unique_ptr<Process>> loggers;
  std::vector<std::string> files;
  for (int i = 0; i < 3; ++i) {
    files.push_back(token_file_ + ".log" + std::to_string(i) + ".csv");
    loggers.push_back(std::make_unique<Process>(std::vector<std::string>{
        kCli, "log", id, "--csv", files.back(), "--duration", "60", "--lcm-url", kUrl}));
  }
  for (auto& l : loggers) ASSERT_TRUE(l->waitForError("log: recording", 30));  // subscribed
  ASSERT_EQ(cli({"mode", id, "fast"}, true).status, 0);
  std::vector<std::string> csv;
  for (int i = 0; i < 3; ++i) {
    const Result r = loggers[i]->wait(60);  // ends when the session finishes
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("0 lost"), std::string::npos) << r.err;
    csv.push_back(readText(files[i]));
    std::remove(files[i].c_str());
  }
  // 1 s at 50 Hz: 50 frames after t = 0 (the finishing frame repeats t = 1)
  EXPECT_GE(lines(csv[0]).size(), 51u);
  EXPECT_EQ(csv[0], csv[1]);
  EXPECT_EQ(csv[0], csv[2]);
}

TEST_F(Service, TorqueCommandChangesTheMotion) {
  const std::string driven = create({"--mode", "lockstep"});
  const std::string coasting = create({"--mode", "lockstep"});
  // forward torque on every wheel, held after the client leaves
  const Result d = cli({"drive", driven, "--hold"}, true, "throttle 2\nquit\n");
  ASSERT_EQ(d.status, 0) << d.err;
  const Result a = step(driven, 20000);  // 1 s
  const Result b = step(coasting, 20000);
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  const std::string la = lines(a.out).at(0), lb = lines(b.out).at(0);
  const double speed_a = std::hypot(field(la, kVx), field(la, kVy));
  const double speed_b = std::hypot(field(lb, kVx), field(lb, kVy));
  // the same car from the same start: driving torque makes it faster and farther
  EXPECT_GT(speed_a, speed_b + 0.1) << la << "\n" << lb;
  EXPECT_GT(field(la, kX), field(lb, kX)) << la << "\n" << lb;
}

// A create with a tolerance (docs/accuracy.md): the server's pilot replaces
// the file's step (0.004 s, off the ladder) with one of its ladder, 0.02 s /
// 2^k, and the session runs it; a tolerance out of range is refused naming
// the field, and the server keeps serving.
TEST_F(Service, ATolerancePicksTheStepTheSessionRuns) {
  const std::string file = tokenFile("slalom_tolerance") + ".json";
  slalomWithAccuracy(file, "{\"tolerance\": 0.01, \"pilot_duration\": 1}");
  const Result c = cli({"create", file, "--mode", "lockstep", "--duration", "2"}, true);
  ASSERT_EQ(c.status, 0) << c.err;
  const std::string id = lastLine(c.out);
  ASSERT_EQ(step(id, 10).status, 0);
  const Result l = cli({"list"}, false);
  ASSERT_EQ(l.status, 0) << l.err;
  double dt = 0.0;
  for (const std::string& line : lines(l.out))
    if (line.rfind(id, 0) == 0) dt = field(line, 7);  // SESSION NAME MODE STATUS T TICK RATE DT
  ASSERT_GT(dt, 0.0) << l.out;
  const double k = std::log2(0.02 / dt);
  EXPECT_NEAR(k, std::round(k), 1e-6) << "dt " << dt << " is not 0.02 s / 2^k";
  EXPECT_NE(dt, 0.004);

  slalomWithAccuracy(file, "{\"tolerance\": 0}");
  const Result refused = cli({"create", file, "--mode", "lockstep"}, true);
  EXPECT_NE(refused.status, 0);
  EXPECT_NE((refused.out + refused.err).find("/accuracy/tolerance"), std::string::npos) << refused.err;
  EXPECT_EQ(step(id, 10).status, 0);  // the first session is untouched
  std::remove(file.c_str());
}

TEST_F(Service, LockstepIsBitIdenticalAcrossRuns) {
  auto runOnce = [&] {
    const std::string id = create({"--mode", "lockstep"});
    std::string out;
    EXPECT_EQ(cli({"drive", id, "--hold"}, true, "wheels 1.5 0.5 1.5 0.5\nquit\n").status, 0);
    out += step(id, 1000, 4).out;
    EXPECT_EQ(cli({"drive", id, "--hold"}, true, "brake 1\nquit\n").status, 0);
    out += step(id, 1000, 4).out;
    return out;
  };
  const std::string first = runOnce();
  ASSERT_TRUE(stopServer().status == 0);
  startServer();  // a fresh server process: nothing carried over
  const std::string second = runOnce();
  EXPECT_EQ(lines(first).size(), 8u);
  EXPECT_EQ(first, second);
}

TEST_F(Service, OwnershipRefusedWithoutToken) {
  const std::string id = create({"--mode", "lockstep"});
  const Result wrong = cli({"step", id, "10", "--token", "00000000000000000000000000000000"}, true);
  EXPECT_EQ(wrong.status, 1);
  EXPECT_NE(wrong.err.find("wrong token"), std::string::npos) << wrong.err;
  const Result none = cli({"stop", id, "--token-file", token_file_ + ".empty"}, false);
  EXPECT_EQ(none.status, 1);
  EXPECT_NE(none.err.find("needs its token"), std::string::npos) << none.err;
  const Result drive = cli({"drive", id, "--token", "bad"}, true, "throttle 1\nquit\n");
  EXPECT_EQ(drive.status, 1);
  EXPECT_NE(drive.err.find("wrong token"), std::string::npos) << drive.err;
  // the owner still controls it, and anyone may watch
  EXPECT_EQ(step(id, 10).status, 0);
  EXPECT_NE(cli({"list"}, false).out.find(id), std::string::npos);
}

// Collects server events in this process.
class EventListener {
 public:
  EventListener() : lcm_(kUrl) {
    lcm_.subscribeFunction(net::kEventChannel, &EventListener::onEvent, this);
  }
  lcm::LCM& lcm() { return lcm_; }
  // Waits for the next event with this code and consumes it; returns its
  // reason ("" on timeout).
  std::string waitFor(int code, double timeout_s = 10) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < end) {
      for (auto it = events_.begin(); it != events_.end(); ++it)
        if (it->code == code) {
          const std::string reason = it->reason.empty() ? "?" : it->reason;
          events_.erase(it);
          return reason;
        }
      lcm_.handleTimeout(50);
    }
    return "";
  }

 private:
  static void onEvent(const lcm::ReceiveBuffer* rbuf, const std::string&, EventListener* self) {
    groundsim::event_t e;
    if (net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), e, "event_t").ok())
      self->events_.push_back(e);
  }
  lcm::LCM lcm_;
  std::vector<groundsim::event_t> events_;
};

TEST_F(Service, BadInputIsAnsweredAndTheServerKeepsServing) {
  const std::string good = create({"--mode", "lockstep"});
  EventListener events;
  ASSERT_TRUE(events.lcm().good());

  // undecodable datagrams: too short for any message, and a request cut short
  const std::string tiny = "abc";
  events.lcm().publish(net::kDriveChannel, tiny.data(), static_cast<unsigned>(tiny.size()));
  EXPECT_NE(events.waitFor(groundsim::event_t::ERR_DECODE + 0).find("cannot hold"), std::string::npos);
  groundsim::request_t req{};
  req.op = groundsim::request_t::OP_LIST;
  std::vector<uint8_t> buf(req.getEncodedSize());
  req.encode(buf.data(), 0, static_cast<int>(buf.size()));
  events.lcm().publish(net::kRequestChannel, buf.data(), static_cast<unsigned>(buf.size() - 5));
  const std::string cut = events.waitFor(groundsim::event_t::ERR_DECODE + 0);
  EXPECT_TRUE(cut.find("malformed") != std::string::npos || cut.find("cannot hold") != std::string::npos) << cut;
  // another type on the request channel: wrong fingerprint
  groundsim::event_t other{};
  events.lcm().publish(net::kRequestChannel, &other);
  const std::string fp = events.waitFor(groundsim::event_t::ERR_FINGERPRINT + 0);
  EXPECT_NE(fp.find("fingerprint"), std::string::npos) << fp;

  // unknown session
  const Result unknown = cli({"step", "DEADBEEF", "1", "--token", "x"}, true);
  EXPECT_EQ(unknown.status, 1);
  EXPECT_NE(unknown.err.find("unknown session"), std::string::npos) << unknown.err;

  // invalid scenario: the scenario layer's path-named errors
  const std::string bad_file = token_file_ + ".bad.json";
  {
    std::ofstream f(bad_file);
    f << R"({"name": "bad", "duration": -1, "ground": {"type": "plane"}, "vehicle": {"name": "car"}})";
  }
  const Result bad = cli({"create", bad_file}, true);
  std::remove(bad_file.c_str());
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("/duration"), std::string::npos) << bad.err;

  // NaN, infinite and huge torques
  for (const std::string& wheels : {"wheels nan 0 0 0", "wheels 0 inf 0 0", "wheels 1e9 0 0 0", "wheels 0 0 0 0 -5 0 0 0"}) {
    const Result d = cli({"drive", good}, true, wheels + "\nquit\n");
    EXPECT_EQ(d.status, 1) << wheels;
    EXPECT_NE(d.err.find("refused"), std::string::npos) << wheels << ": " << d.err;
  }
  const Result nan = cli({"drive", good}, true, "wheels nan 0 0 0\nquit\n");
  EXPECT_NE(nan.err.find("non-finite"), std::string::npos) << nan.err;

  // too many sessions (the server allows 4)
  for (int i = 0; i < 3; ++i) create({"--mode", "lockstep"});
  const Result full = cli({"create", kPlain}, true);
  EXPECT_EQ(full.status, 1);
  EXPECT_NE(full.err.find("too many sessions"), std::string::npos) << full.err;

  // still serving, and the first session was not disturbed by any of it
  const Result s = step(good, 100);
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_EQ(field(lines(s.out).at(0), 0), 100);
  EXPECT_EQ(cli({"list"}, false).status, 0);
}

TEST_F(Service, CleanShutdownOnSigterm) {
  const std::string id = create({"--duration", "-1"});
  Process watcher({kCli, "watch", id, "--duration", "60", "--lcm-url", kUrl});
  ASSERT_TRUE(watcher.waitForOutput("running", 30));
  const Result srv = stopServer();
  EXPECT_EQ(srv.status, 0) << srv.err;
  EXPECT_NE(srv.out.find("stopped"), std::string::npos) << srv.out;
  // subscribers see the session's last state, with status stopped, and leave
  const Result w = watcher.wait(30);
  EXPECT_EQ(w.status, 0) << w.err;
  EXPECT_NE(lastLine(w.out).find("stopped"), std::string::npos) << w.out;
  // no server: clients say so instead of hanging
  const Result list = cli({"list", "--timeout", "0.5"}, false);
  EXPECT_EQ(list.status, 4);  // kExitNoServer
  EXPECT_NE(list.err.find("no reply"), std::string::npos) << list.err;
}

}  // namespace
// A tolerance no setting meets: the session's live error estimate passes
// it while the session steps, so the session refines its step at safe
// points, twice (accuracy.max_refinements 2), each said in an info event,
// and then says once, in a warning event, that no refinement is left.
TEST_F(Service, TheLiveEstimateWarnsWhenItPassesTheTolerance) {
  const std::string file = tokenFile("slalom_tight") + ".json";
  slalomWithAccuracy(file, "{\"tolerance\": 1e-6, \"pilot_duration\": 1, \"max_refinements\": 2}");
  EventListener events;
  ASSERT_TRUE(events.lcm().good());
  const Result c = cli({"create", file, "--mode", "lockstep", "--duration", "4"}, true);
  ASSERT_EQ(c.status, 0) << c.err;
  const std::string id = lastLine(c.out);
  std::vector<std::string> said;  // the accuracy events, in order
  bool warned = false;
  // the windows of a 4 s run are 1/16 s long: a few hundred steps each at
  // the chosen step; step on until the warning (or the session's end)
  const auto hear = [&](double wait_s) {
    for (std::string r; !warned && !(r = events.waitFor(groundsim::event_t::ERR_NONE + 0, wait_s)).empty();) {
      if (r.rfind("accuracy:", 0) != 0) continue;
      said.push_back(r);
      warned = warned || r.find("max_refinements") != std::string::npos;
    }
  };
  for (int round = 0; round < 40 && !warned; ++round) {
    if (step(id, 400).status != 0) break;
    hear(0.5);  // what came meanwhile; what comes later is heard after a later round
  }
  // the events of the last rounds, however late a loaded machine publishes
  // them: the steps are done, so waiting longer only ends a hung test
  if (!warned) hear(60);
  std::string all;
  for (const std::string& r : said) all += r + "\n";
  ASSERT_EQ(said.size(), 3u) << all;
  EXPECT_NE(said[0].find("passed the tolerance 1e-06: refined to 2 integrator substeps per step (from 1)"),
            std::string::npos) << all;
  EXPECT_NE(said[1].find("refined to 4 integrator substeps per step (from 2)"), std::string::npos) << all;
  EXPECT_NE(said[2].find("passed the tolerance 1e-06"), std::string::npos) << all;
  EXPECT_NE(said[2].find("2 refinements, the most: accuracy.max_refinements"), std::string::npos) << all;
  std::remove(file.c_str());
}

}  // namespace groundsim::itest
