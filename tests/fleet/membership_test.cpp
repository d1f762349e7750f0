// Membership against a real etcd (etcd_lab.sh: a private network namespace).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <thread>

#include "etcd_process.hpp"
#include "fleet/membership.hpp"

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

Membership::Options options(const std::string& id) {
  Membership::Options o;
  o.id = id;
  o.address = "192.0.2.10";
  o.build = "test";
  o.prefix = "/gs-test";
  o.capacity = {{"sessions_free", 100}, {"max_sessions", 100}, {"workers", 2}, {"load", 0.0}};
  return o;
}

bool sees(const Membership& m, const std::string& id) { return m.member(id).has_value(); }

TEST(Membership, TwoMembersSeeEachOther) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  Membership a(c, options("a")), b(c, options("b"));
  EXPECT_EQ(a.ttl(), 2);
  EXPECT_TRUE(a.healthy());
  EXPECT_NE(a.leaseId(), 0);
  EXPECT_NE(a.leaseId(), b.leaseId());
  ASSERT_TRUE(waitFor([&] { return sees(a, "b") && sees(b, "a") && sees(a, "a"); }, 3.0));
  auto seen = b.member("a");
  EXPECT_EQ(seen->lease, a.leaseId());
  EXPECT_EQ(seen->info["id"], "a");
  EXPECT_EQ(seen->info["address"], "192.0.2.10");
  EXPECT_EQ(seen->info["build"], "test");
  EXPECT_EQ(seen->info["capacity"]["max_sessions"], 100);
  EXPECT_EQ(seen->info["draining"], false);
  EXPECT_GT(seen->info["started_utime"].get<std::int64_t>(), 0);
  // the key, as etcd holds it
  auto kv = c.get("/gs-test/servers/a");
  ASSERT_TRUE(kv.has_value());
  EXPECT_EQ(kv->lease, a.leaseId());

  a.update({{"sessions_free", 7}, {"max_sessions", 100}, {"workers", 2}, {"load", 0.5}});
  a.setDraining(true);
  ASSERT_TRUE(waitFor([&] {
    auto m = b.member("a");
    return m && m->info["capacity"]["sessions_free"] == 7 && m->info["draining"] == true;
  }, 3.0)) << "b never saw a's update";
  EXPECT_EQ(b.member("a")->lease, a.leaseId());  // still bound to the lease
  // kept alive past several TTLs
  std::this_thread::sleep_for(std::chrono::seconds(2 * a.ttl()));
  EXPECT_TRUE(a.healthy());
  EXPECT_TRUE(sees(b, "a"));
  EXPECT_TRUE(a.lastError().empty()) << a.lastError();
}

TEST(Membership, AMemberWhoseThreadStopsIsGoneFromTheOthersView) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  std::mutex mu;
  std::vector<std::vector<std::string>> views;
  Membership::Callbacks cb;
  cb.on_members = [&](const std::vector<Member>& v) {
    std::vector<std::string> ids;
    for (auto& m : v) ids.push_back(m.id);
    std::lock_guard lock(mu);
    views.push_back(ids);
  };
  Membership watcher(c, options("watcher"), cb);
  auto dying = std::make_unique<Membership>(c, options("dying"));
  ASSERT_TRUE(waitFor([&] { return sees(watcher, "dying"); }, 3.0));
  // its thread stops without a word (as a process that dies): its key lapses with the lease
  const auto ttl = dying->ttl();
  dying->abandon();
  const auto stopped = Clock::now();
  EXPECT_TRUE(c.get("/gs-test/servers/dying").has_value()) << "gone before its lease lapsed";
  ASSERT_TRUE(waitFor([&] { return !sees(watcher, "dying"); }, ttl + 3.0)) << "still in the view after TTL + 3 s";
  std::printf("abandoned member gone from the other's view %.2f s after its thread stopped (TTL %lld s)\n",
              secondsSince(stopped), static_cast<long long>(ttl));
  EXPECT_FALSE(c.get("/gs-test/servers/dying").has_value());
  {
    std::lock_guard lock(mu);
    ASSERT_FALSE(views.empty());
    EXPECT_EQ(views.back(), std::vector<std::string>{"watcher"});  // on_members told the change
  }
  // one that leaves revokes its lease: gone at once
  auto leaving = std::make_unique<Membership>(c, options("leaving"));
  ASSERT_TRUE(waitFor([&] { return sees(watcher, "leaving"); }, 3.0));
  leaving.reset();
  EXPECT_FALSE(c.get("/gs-test/servers/leaving").has_value());
  EXPECT_TRUE(waitFor([&] { return !sees(watcher, "leaving"); }, 2.0));
  EXPECT_TRUE(watcher.healthy());
}

TEST(Membership, TheSameIdTwiceIsRefusedWhileTheFirstLives) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  auto first = std::make_unique<Membership>(c, options("same"));
  try {
    Membership second(c, options("same"));
    FAIL() << "a second server took the id of a live one";
  } catch (const MembershipError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("'same' is taken"), std::string::npos) << what;
    EXPECT_NE(what.find(std::to_string(first->leaseId())), std::string::npos) << what;
  }
  EXPECT_EQ(c.get("/gs-test/servers/same")->lease, first->leaseId());  // untouched
  EXPECT_TRUE(first->healthy());
  // the first dies: refused until its lease lapses, then taken
  const auto ttl = first->ttl();
  first->abandon();
  const auto died = Clock::now();
  EXPECT_THROW(Membership(c, options("same")), MembershipError);
  std::unique_ptr<Membership> second;
  ASSERT_TRUE(waitFor([&] {
    try {
      second = std::make_unique<Membership>(c, options("same"));
      return true;
    } catch (const MembershipError&) {
      return false;
    }
  }, ttl + 3.0)) << "the id stayed taken after the first's lease";
  std::printf("same id taken again %.2f s after the first died (TTL %lld s)\n", secondsSince(died),
              static_cast<long long>(ttl));
  EXPECT_TRUE(second->healthy());
  EXPECT_EQ(c.get("/gs-test/servers/same")->lease, second->leaseId());
  EXPECT_THROW(Membership(c, options("bad/id")), std::invalid_argument);
}

TEST(Membership, OnLostFiresWhenEtcdIsKilled) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  std::atomic<int> lost{0};
  std::atomic<double> lost_at{0};
  std::string reason;
  std::mutex mu;
  const auto t0 = Clock::now();
  Membership::Callbacks cb;
  cb.on_lost = [&](const std::string& why) {
    lost_at = secondsSince(t0);
    std::lock_guard lock(mu);
    reason = why;
    ++lost;
  };
  Membership m(c, options("solo"), cb);
  std::this_thread::sleep_for(std::chrono::seconds(m.ttl() + 1));
  EXPECT_EQ(lost.load(), 0) << "lost while etcd was up";
  EXPECT_TRUE(m.healthy());
  const double killed = secondsSince(t0);
  etcd.kill();
  ASSERT_TRUE(waitFor([&] { return lost.load() > 0; }, m.ttl() + 3.0)) << "no on_lost within TTL + 3 s";
  std::printf("on_lost %.2f s after etcd was killed (TTL %lld s)\n", lost_at.load() - killed,
              static_cast<long long>(m.ttl()));
  EXPECT_FALSE(m.healthy());
  EXPECT_EQ(m.leaseId(), 0);
  {
    std::lock_guard lock(mu);
    EXPECT_NE(reason.find("no lease renewal"), std::string::npos) << reason;
  }
  std::this_thread::sleep_for(1s);
  EXPECT_EQ(lost.load(), 1) << "on_lost once per loss";
  EXPECT_FALSE(m.lastError().empty());
}

TEST(Membership, ReRegistersWithANewLeaseWhenEtcdIsBack) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  std::atomic<int> lost{0}, registered{0};
  std::atomic<std::int64_t> new_lease{0};
  Membership::Callbacks cb;
  cb.on_lost = [&](const std::string&) { ++lost; };
  cb.on_registered = [&](std::int64_t lease) {
    new_lease = lease;
    ++registered;
  };
  Membership m(c, options("phoenix"), cb);
  const auto first_lease = m.leaseId();
  etcd.kill();
  ASSERT_TRUE(waitFor([&] { return lost.load() > 0; }, m.ttl() + 3.0));
  EXPECT_EQ(registered.load(), 0);
  std::this_thread::sleep_for(1s);  // etcd stays away a while
  EXPECT_EQ(registered.load(), 0) << "registered without etcd";
  const auto restarted = Clock::now();
  etcd.start();  // returns when it answers
  const auto answered = Clock::now();
  ASSERT_TRUE(waitFor([&] { return registered.load() > 0; }, 10.0)) << "not registered again: " << m.lastError();
  std::printf("registered again %.2f s after etcd was restarted, %.2f s after it answered\n", secondsSince(restarted),
              secondsSince(answered));
  EXPECT_TRUE(m.healthy());
  EXPECT_NE(m.leaseId(), 0);
  EXPECT_NE(m.leaseId(), first_lease);
  EXPECT_EQ(m.leaseId(), new_lease.load());
  auto kv = c.get("/gs-test/servers/phoenix");
  ASSERT_TRUE(kv.has_value());
  EXPECT_EQ(kv->lease, m.leaseId());
  EXPECT_EQ(c.leaseKeepAliveOnce(first_lease), 0) << "the lost lease was not revoked";
  ASSERT_TRUE(waitFor([&] { return m.member("phoenix") && m.member("phoenix")->lease == m.leaseId(); }, 3.0));
  // and it stays registered
  std::this_thread::sleep_for(std::chrono::seconds(m.ttl() + 1));
  EXPECT_TRUE(m.healthy());
  EXPECT_EQ(lost.load(), 1);
}

TEST(Membership, ResumesItsLeaseWhenEtcdStillHoldsIt) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  std::atomic<int> lost{0}, registered{0};
  std::atomic<std::int64_t> back_with{0};
  Membership::Callbacks cb;
  cb.on_lost = [&](const std::string&) { ++lost; };
  cb.on_registered = [&](std::int64_t lease) {
    back_with = lease;
    ++registered;
  };
  auto o = options("keeper");
  o.resume_lease = true;
  Membership m(c, o, cb);
  const auto first_lease = m.leaseId();
  c.put("/gs-test/owned/s1", "keeper", first_lease);  // something the owner holds under its lease
  etcd.kill();
  ASSERT_TRUE(waitFor([&] { return lost.load() > 0; }, m.ttl() + 3.0));
  m.update({{"sessions_free", 3}});  // changed while lost: published once back
  etcd.start();  // etcd restores its leases and extends them
  ASSERT_TRUE(waitFor([&] { return registered.load() > 0; }, 10.0)) << m.lastError();
  EXPECT_EQ(back_with.load(), first_lease);
  EXPECT_EQ(m.leaseId(), first_lease);
  EXPECT_TRUE(m.healthy());
  auto owned = c.get("/gs-test/owned/s1");
  ASSERT_TRUE(owned.has_value()) << "a resumed lease keeps its keys";
  EXPECT_EQ(owned->lease, first_lease);
  ASSERT_TRUE(waitFor([&] {
    auto kv = c.get("/gs-test/servers/keeper");
    return kv && kv->lease == first_lease && nlohmann::json::parse(kv->value)["capacity"]["sessions_free"] == 3;
  }, 3.0));
  EXPECT_EQ(lost.load(), 1);
}

TEST(Membership, ALeaseEtcdEndedIsLostAtOnceAndReplaced) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  std::atomic<int> lost{0}, registered{0};
  std::string reason;
  std::mutex mu;
  Membership::Callbacks cb;
  cb.on_lost = [&](const std::string& why) {
    std::lock_guard lock(mu);
    reason = why;
    ++lost;
  };
  cb.on_registered = [&](std::int64_t) { ++registered; };
  Membership m(c, options("revoked"), cb);
  const auto first = m.leaseId();
  c.leaseRevoke(first);  // as if it had expired in etcd (a stalled process)
  ASSERT_TRUE(waitFor([&] { return lost.load() > 0; }, 3.0));
  {
    std::lock_guard lock(mu);
    EXPECT_NE(reason.find("expired"), std::string::npos) << reason;
  }
  ASSERT_TRUE(waitFor([&] { return registered.load() > 0 && m.healthy(); }, 3.0));
  EXPECT_NE(m.leaseId(), first);
  EXPECT_EQ(c.get("/gs-test/servers/revoked")->lease, m.leaseId());
}

}  // namespace
}  // namespace groundsim::fleet
