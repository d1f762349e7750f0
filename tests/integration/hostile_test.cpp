// Hostile and unlucky clients against the real groundsim-server and the
// real `groundsim` clients (docs/reliability.md): extreme settings
// are refused with the field named, clients notice a server that was
// killed, `log` accounts for every seq and learns a session's end from the
// heartbeat, oversized creates are refused before sending, usage errors
// exit 2 with short, escaped messages. Verdicts are exit codes and
// messages; waits are bounded and generous.
#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "process.hpp"
#include "test_env.hpp"

namespace groundsim::itest {
namespace {

constexpr int kRefused = 1, kUsage = 2, kLoss = 3, kNoServer = 4;

class Hostile : public ::testing::Test {
 protected:
  void SetUp() override {
    token_file_ = tokenFile("hostile");
    std::remove(token_file_.c_str());
    server_ = std::make_unique<Process>(
        std::vector<std::string>{kServer, "--lcm-url", kUrl, "--workers", "2", "--max-sessions", "8"});
    ASSERT_TRUE(server_->waitForOutput("groundsim-server ready", 20)) << server_->wait(1).err;
  }
  void TearDown() override {
    if (server_) {
      server_->signal(SIGTERM);
      server_->wait(30);
    }
    for (const auto& f : files_) std::remove(f.c_str());
    std::remove(token_file_.c_str());
    std::remove((token_file_ + ".lock").c_str());
  }
  std::vector<std::string> argv(std::vector<std::string> args, bool net = true) {
    const bool owner = args[0] != "list" && args[0] != "watch";  // the others take a token
    args.insert(args.begin(), kCli);
    if (net) args.insert(args.end(), {"--lcm-url", kUrl});
    if (net && owner) args.insert(args.end(), {"--token-file", token_file_});
    if (net) withReplyTimeout(args);
    return args;
  }
  Result cli(std::vector<std::string> args, bool net = true, const std::string& in = "") {
    return run(argv(std::move(args), net), in, 120);
  }
  std::string create(std::vector<std::string> extra) {
    std::vector<std::string> args{"create", kPlain};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = cli(args);
    EXPECT_EQ(r.status, 0) << r.err;
    return lastLine(r.out);
  }
  std::string file(const std::string& tag) {
    files_.push_back(token_file_ + "." + tag);
    return files_.back();
  }

  std::unique_ptr<Process> server_;
  std::string token_file_;
  std::vector<std::string> files_;
};

TEST_F(Hostile, ExtremeRatesAreRefusedNamingTheField) {
  const Result slow = cli({"create", kPlain, "--rate", "1e-12"});
  EXPECT_EQ(slow.status, kRefused);
  EXPECT_NE(slow.err.find("rate: 1e-12 is outside [0.001, 1000]"), std::string::npos) << slow.err;
  const Result sparse = cli({"create", kPlain, "--publish-rate", "1e-300"});
  EXPECT_EQ(sparse.status, kRefused);
  EXPECT_NE(sparse.err.find("publish_rate: 1e-300 is outside"), std::string::npos) << sparse.err;
  const Result list = cli({"list"});
  EXPECT_EQ(list.status, 0);
  EXPECT_EQ(std::count(list.out.begin(), list.out.end(), '\n'), 1) << "no session was created: " << list.out;
}

TEST_F(Hostile, ClientsExitNonZeroWhenTheServerIsKilled) {
  const std::string id = create({"--duration", "-1"});
  const std::string lock = create({"--mode", "lockstep"});
  Process log(argv({"log", id, "--csv", file("log.csv")}));
  Process watch(argv({"watch", id}));
  Process drive(argv({"drive", id}), "throttle 1\nwait 600\n");
  ASSERT_TRUE(log.waitForError("log: recording", 30));
  ASSERT_TRUE(watch.waitForError("subscribed", 30));
  ASSERT_TRUE(drive.waitForError("sending", 30));
  Process step(argv({"step", lock, "3000000"}));  // minutes of stepping: the reply would come long after
  server_->signal(SIGKILL);
  server_->wait(30);
  server_.reset();
  for (Process* p : {&log, &watch, &drive, &step}) {
    const Result r = p->wait(60);  // the heartbeat timeout is 3 s
    EXPECT_EQ(r.status, kNoServer) << r.err;
    EXPECT_NE(r.err.find("no heartbeat from groundsim-server"), std::string::npos) << r.err;
  }
}

TEST_F(Hostile, LogCreatesItsSessionAndAccountsFromSeqZero) {
  const std::string csv = file("from0.csv");
  const Result r = cli({"log", "--create", kPlain, "--mode", "fast", "--session-duration", "0.5", "--csv", csv});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("states received (seq 0.."), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(", 0 lost in 0 gaps, session ended"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("session ended"), std::string::npos) << r.err;
}

TEST_F(Hostile, LogLearnsAnEndItDidNotHearFromTheHeartbeat) {
  // the session ended before this log subscribed: its final state will
  // never come, and log used to wait for it forever
  const std::string done = create({"--mode", "fast", "--duration", "0.2"});
  const std::string stopped = create({"--duration", "-1"});
  ASSERT_EQ(cli({"stop", stopped}).status, 0);
  // 0.2 s of the ring car is quick, not instant (a sanitizer build is 5-15x slower)
  bool finished = false;
  for (int i = 0; i < 600 && !finished; ++i) {
    const Result list = cli({"list"});
    for (size_t at = list.out.find(done); at != std::string::npos && !finished; at = list.out.find(done, at + 1))
      finished = list.out.substr(at, list.out.find('\n', at) - at).find("finished") != std::string::npos;
    if (!finished) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(finished) << "session " << done << " never finished";
  for (const auto& id : {done, stopped}) {
    const Result r = cli({"log", id, "--csv", file(id + ".csv")});
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("from the server's heartbeat"), std::string::npos) << r.err;
  }
  const Result unknown = cli({"log", "DEADBEEF", "--csv", file("unknown.csv")});
  EXPECT_EQ(unknown.status, kRefused) << unknown.err;
  EXPECT_NE(unknown.err.find("not on the server"), std::string::npos) << unknown.err;
  const Result watch = cli({"watch", "DEADBEEF"});
  EXPECT_EQ(watch.status, kRefused) << watch.err;
}

TEST_F(Hostile, OversizedCreateIsRefusedBeforeSending) {
  const std::string big = file("big.json");
  {
    std::ofstream f(big);
    f << R"({"name": ")" << std::string(2 << 20, 'x') << R"(", "ground": {"type": "plane"}, "vehicle": {}})";
  }
  const Result r = cli({"create", big});
  EXPECT_EQ(r.status, kRefused);
  EXPECT_NE(r.err.find("bytes a create can carry"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("no reply"), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 1000u);
}

TEST_F(Hostile, UsageErrorsExitTwoWithShortEscapedMessages) {
  const Result unknown = cli({"frobnicate"}, false);
  EXPECT_EQ(unknown.status, kUsage);
  EXPECT_NE(unknown.err.find("unknown subcommand \"frobnicate\""), std::string::npos) << unknown.err;
  EXPECT_EQ(cli({"create"}, false).status, kUsage);                    // missing SCENARIO
  EXPECT_EQ(cli({"step", "A", "many"}, false).status, kUsage);         // not a number
  EXPECT_EQ(cli({"create", kPlain, "--mode", "warp"}, false).status, kUsage);
  EXPECT_EQ(cli({"watch", "A", "--bogus"}, false).status, kUsage);
  const std::string huge(100000, 'n');
  const Result h = cli({"watch", "A", "--count", huge + std::string("\x1b[2J")}, false);
  EXPECT_EQ(h.status, kUsage);
  EXPECT_LT(h.err.size(), 1000u) << "the value was echoed whole";
  EXPECT_EQ(h.err.find('\x1b'), std::string::npos) << "an escape reached the terminal";
  EXPECT_EQ(cli({"run", kPlain, "--dt", "fast"}, false).status, kUsage);
}

TEST_F(Hostile, CreateTakesAPreset) {
  const Result r = cli({"create", kPlain, "--preset", "fast", "--mode", "lockstep"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(cli({"create", kPlain, "--preset", "nonsense"}).status, kUsage);
}

// A client on the bus that creates in a loop (a shell loop of `groundsim
// create`: one principal, user@host or GROUNDSIM_CLIENT) is refused at the
// server's --client-sessions, naming the limit and the flag, while another
// client still creates (docs/reliability.md, Fairness).
TEST_F(Hostile, ACreateLoopIsRefusedAtItsLimitWhileAnotherClientCreates) {
  // this case's own server: --client-sessions 3
  server_->signal(SIGTERM);
  server_->wait(30);
  server_ = std::make_unique<Process>(std::vector<std::string>{kServer, "--lcm-url", kUrl, "--workers", "2",
                                                               "--max-sessions", "8", "--client-sessions", "3"});
  ASSERT_TRUE(server_->waitForOutput("groundsim-server ready", 20)) << server_->wait(1).err;
  const std::string tokens = token_file_;
  auto create = [&](const char* client) {
    ::setenv("GROUNDSIM_CLIENT", client, 1);
    std::vector<std::string> args{kCli, "create", kPlain, "--duration", "-1", "--lcm-url", kUrl, "--token-file", tokens};
    withReplyTimeout(args);
    Result r = run(args, "", 120);
    ::unsetenv("GROUNDSIM_CLIENT");
    return r;
  };
  int made = 0;
  Result refused;
  for (int k = 0; k < 6 && refused.err.empty(); ++k) {
    Result r = create("looper");
    if (r.status == 0) ++made;
    else refused = r;
  }
  EXPECT_EQ(made, 3) << "the loop's creates up to --client-sessions";
  EXPECT_EQ(refused.status, kRefused) << refused.err;
  EXPECT_NE(refused.err.find("too many sessions for client 'cli-looper': it holds 3, at most 3 (server --client-sessions"),
            std::string::npos)
      << refused.err;
  const Result other = create("someone-else");
  EXPECT_EQ(other.status, 0) << "another client still creates: " << other.err;
}

}  // namespace
}  // namespace groundsim::itest
