// Watch against a real etcd (etcd_lab.sh: a private network namespace).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <thread>

#include "etcd_process.hpp"
#include "fleet/watch.hpp"

namespace groundsim::fleet {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using test::EtcdProcess;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

template <class Pred>
bool waitFor(Pred pred, double timeout_s) {
  const auto start = Clock::now();
  while (secondsSince(start) < timeout_s) {
    if (pred()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return pred();
}

struct Recorder {
  std::mutex mu;
  std::vector<Watch::Event> events;
  std::vector<std::string> errors;
  Watch::EventFn onEvent() {
    return [this](const Watch::Event& e) {
      std::lock_guard lock(mu);
      events.push_back(e);
    };
  }
  Watch::ErrorFn onError() {
    return [this](const std::string& e) {
      std::lock_guard lock(mu);
      errors.push_back(e);
    };
  }
  std::size_t count() {
    std::lock_guard lock(mu);
    return events.size();
  }
  std::vector<Watch::Event> copy() {
    std::lock_guard lock(mu);
    return events;
  }
};

TEST(Watch, DeliversPutsAndDeletesInOrderFromARevision) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  const auto first = c.put("/w/a", "1");
  c.put("/other", "not watched");
  c.put("/w/b", std::string("\0\xff", 2));
  Recorder r;
  Watch w(c, "/w/", first, r.onEvent(), r.onError());
  ASSERT_TRUE(waitFor([&] { return r.count() == 2; }, 5.0)) << "the history from the start revision";
  auto lease = c.leaseGrant(2);
  c.put("/w/a", "2");
  c.del("/w/b");
  c.put("/w/leased", "x", lease.id);
  c.leaseRevoke(lease.id);  // its key goes: a DELETE
  ASSERT_TRUE(waitFor([&] { return r.count() == 6; }, 5.0)) << r.count();
  auto ev = r.copy();
  EXPECT_EQ(ev[0].kv.key, "/w/a");
  EXPECT_EQ(ev[0].kv.value, "1");
  EXPECT_EQ(ev[0].kv.mod_revision, first);
  EXPECT_EQ(ev[1].kv.value, std::string("\0\xff", 2));
  EXPECT_EQ(ev[2].type, Watch::Event::Type::Put);
  EXPECT_EQ(ev[2].kv.version, 2);
  EXPECT_EQ(ev[3].type, Watch::Event::Type::Delete);
  EXPECT_EQ(ev[3].kv.key, "/w/b");
  EXPECT_EQ(ev[4].kv.lease, lease.id);
  EXPECT_EQ(ev[5].type, Watch::Event::Type::Delete);
  EXPECT_EQ(ev[5].kv.key, "/w/leased");
  for (std::size_t i = 1; i < ev.size(); ++i) EXPECT_GT(ev[i].kv.mod_revision, ev[i - 1].kv.mod_revision);
  EXPECT_EQ(w.lastRevision(), ev.back().kv.mod_revision);
  EXPECT_TRUE(w.connected());
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(r.count(), 6u) << "nothing else: /other is outside the prefix";
}

TEST(Watch, ReopensAfterEtcdRestartsWithoutLosingOrRepeating) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  Recorder r;
  Watch w(c, "/w/", 0, r.onEvent(), r.onError());  // from now on
  ASSERT_TRUE(waitFor([&] { return w.connected(); }, 5.0));
  for (int i = 0; i < 5; ++i) c.put("/w/" + std::to_string(i), "before");
  ASSERT_TRUE(waitFor([&] { return r.count() == 5; }, 5.0));
  etcd.kill();
  ASSERT_TRUE(waitFor([&] { return !w.connected(); }, 5.0)) << "the broken stream went unnoticed";
  std::this_thread::sleep_for(500ms);
  etcd.start();
  for (int i = 5; i < 10; ++i) c.put("/w/" + std::to_string(i), "after");
  ASSERT_TRUE(waitFor([&] { return r.count() >= 10; }, 10.0)) << r.count();
  std::this_thread::sleep_for(300ms);
  auto ev = r.copy();
  ASSERT_EQ(ev.size(), 10u) << "an event repeated";
  for (int i = 0; i < 10; ++i) EXPECT_EQ(ev[i].kv.key, "/w/" + std::to_string(i));
  EXPECT_GE(w.streams(), 2);
  std::lock_guard lock(r.mu);
  EXPECT_FALSE(r.errors.empty()) << "the break was not reported";
}

TEST(Watch, ACompactedStartIsReportedAndTheWatchGoesOn) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  const auto first = c.put("/w/k", "1");
  c.put("/w/k", "2");
  const auto third = c.put("/w/k", "3");
  c.call("/v3/kv/compaction", {{"revision", std::to_string(third)}});
  Recorder r;
  Watch w(c, "/w/", first, r.onEvent(), r.onError());
  ASSERT_TRUE(waitFor([&] { return r.count() >= 1; }, 5.0));
  c.put("/w/k", "4");
  ASSERT_TRUE(waitFor([&] { return r.count() >= 2; }, 5.0));
  auto ev = r.copy();
  EXPECT_EQ(ev[0].kv.value, "3");  // from the compaction revision on
  EXPECT_EQ(ev[1].kv.value, "4");
  std::lock_guard lock(r.mu);
  ASSERT_FALSE(r.errors.empty());
  EXPECT_NE(r.errors[0].find("compacted"), std::string::npos) << r.errors[0];
}

TEST(Watch, StopsPromptlyWhileTheStreamIsSilent) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  Recorder r;
  auto w = std::make_unique<Watch>(c, "/w/", 0, r.onEvent(), r.onError());
  ASSERT_TRUE(waitFor([&] { return w->connected(); }, 5.0));
  std::this_thread::sleep_for(300ms);
  const auto t0 = Clock::now();
  w.reset();
  // the stream is silent for good: a watch that waited for it would never
  // stop. Printed; the ceiling only ends that wait (it polls every 100 ms)
  std::printf("stopped while silent in %.3f s\n", secondsSince(t0));
  EXPECT_LT(secondsSince(t0), 20.0);
  // and while etcd is away
  w = std::make_unique<Watch>(c, "/w/", 0, r.onEvent(), r.onError());
  ASSERT_TRUE(waitFor([&] { return w->connected(); }, 5.0));
  etcd.kill();
  std::this_thread::sleep_for(300ms);
  const auto t1 = Clock::now();
  w.reset();
  std::printf("stopped while etcd is away in %.3f s\n", secondsSince(t1));
  EXPECT_LT(secondsSince(t1), 20.0);
}

}  // namespace
}  // namespace groundsim::fleet
