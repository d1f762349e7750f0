// EtcdClient against a real etcd (etcd_lab.sh: a private network namespace;
// etcd_process.hpp starts the member).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "etcd_process.hpp"
#include "fleet/etcd_client.hpp"

namespace groundsim::fleet {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using test::EtcdProcess;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string allBytes() {
  std::string s;
  for (int i = 0; i < 256; ++i) s += static_cast<char>(i);
  return s;
}

TEST(Base64, RoundTripsEveryLengthAndByte) {
  std::string bytes = allBytes();
  for (std::size_t n = 0; n <= 10; ++n) {
    std::string part = bytes.substr(250 - n, n);
    EXPECT_EQ(EtcdClient::base64Decode(EtcdClient::base64Encode(part)), part) << n;
  }
  EXPECT_EQ(EtcdClient::base64Encode("foo"), "Zm9v");
  EXPECT_EQ(EtcdClient::base64Encode("fo"), "Zm8=");
  EXPECT_EQ(EtcdClient::base64Decode(EtcdClient::base64Encode(bytes)), bytes);
  EXPECT_THROW(EtcdClient::base64Decode("Zm9*"), std::invalid_argument);
  EXPECT_EQ(EtcdClient::prefixEnd("/a/"), "/a0");
  EXPECT_EQ(EtcdClient::prefixEnd(std::string("a\xff", 2)), "b");
  EXPECT_EQ(EtcdClient::prefixEnd(""), std::string(1, '\0'));
  EXPECT_EQ(EtcdClient::parseEndpoints(" http://a:1, b:2 ,,"), (std::vector<std::string>{"http://a:1", "b:2"}));
  EXPECT_THROW(EtcdClient({"https://a:1"}), std::invalid_argument);
  EXPECT_THROW(EtcdClient({}), std::invalid_argument);
}

TEST(EtcdClient, PutGetRangeDeleteRoundTripBinarySafe) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  const std::string binary = allBytes();
  const std::string odd_key = std::string("/t/bin\0key\xff", 11);
  const auto rev0 = c.revision();
  const auto rev1 = c.put("/t/a", binary);
  EXPECT_GT(rev1, rev0);
  c.put(odd_key, "");
  c.put("/t/b", "second");
  c.put("/u/outside", "not in /t/");
  EXPECT_EQ(c.revision(), rev1 + 3);

  auto a = c.get("/t/a");
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->value, binary);
  EXPECT_EQ(a->create_revision, rev1);
  EXPECT_EQ(a->mod_revision, rev1);
  EXPECT_EQ(a->version, 1);
  EXPECT_EQ(a->lease, 0);
  auto odd = c.get(odd_key);
  ASSERT_TRUE(odd.has_value());
  EXPECT_EQ(odd->key, odd_key);
  EXPECT_EQ(odd->value, "");
  EXPECT_FALSE(c.get("/t/missing").has_value());

  auto kvs = c.range("/t/");
  ASSERT_EQ(kvs.size(), 3u);
  EXPECT_EQ(kvs[0].key, "/t/a");
  EXPECT_EQ(kvs[1].key, "/t/b");
  EXPECT_EQ(kvs[2].key, odd_key);  // key order: "bin" after "b"
  EXPECT_EQ(c.range("").size(), 4u);
  EXPECT_TRUE(c.range("/nothing/").empty());

  c.put("/t/a", "changed");
  auto a2 = c.get("/t/a");
  EXPECT_EQ(a2->version, 2);
  EXPECT_EQ(a2->create_revision, rev1);
  EXPECT_GT(a2->mod_revision, rev1);

  EXPECT_EQ(c.del("/t/a"), 1);
  EXPECT_EQ(c.del("/t/a"), 0);
  EXPECT_FALSE(c.get("/t/a").has_value());
  EXPECT_EQ(c.delPrefix("/t/"), 2);
  EXPECT_TRUE(c.range("/t/").empty());
  EXPECT_EQ(c.range("/u/").size(), 1u);
}

TEST(EtcdClient, CreateIfAbsentRefusesASecondCreator) {
  EtcdProcess etcd;
  EtcdClient first({etcd.endpoint()}), second({etcd.endpoint()});
  EXPECT_TRUE(first.createIfAbsent("/own/s1", "first"));
  EXPECT_FALSE(second.createIfAbsent("/own/s1", "second"));
  EXPECT_FALSE(first.createIfAbsent("/own/s1", "first again"));
  EXPECT_EQ(first.get("/own/s1")->value, "first");
  // with a lease: another holder's lease is refused, the key stays the first's
  auto l1 = first.leaseGrant(10), l2 = second.leaseGrant(10);
  EXPECT_TRUE(first.createIfAbsent("/own/s2", "one", l1.id));
  EXPECT_FALSE(second.createIfAbsent("/own/s2", "one", l2.id));
  EXPECT_EQ(second.get("/own/s2")->lease, l1.id);
  // once deleted, it can be created again
  first.del("/own/s1");
  EXPECT_TRUE(second.createIfAbsent("/own/s1", "second"));
  EXPECT_EQ(first.get("/own/s1")->value, "second");
}

TEST(EtcdClient, CompareAndSwapSucceedsOnlyOnTheCurrentModRevision) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  EXPECT_FALSE(c.compareAndSwap("/cas", 5, "x"));  // absent: no mod_revision matches but 0
  EXPECT_FALSE(c.get("/cas").has_value());
  EXPECT_TRUE(c.compareAndSwap("/cas", 0, "v1"));  // 0: only if absent
  auto v1 = c.get("/cas");
  ASSERT_TRUE(v1.has_value());
  EXPECT_FALSE(c.compareAndSwap("/cas", 0, "again"));
  EXPECT_FALSE(c.compareAndSwap("/cas", v1->mod_revision - 1, "stale"));
  EXPECT_FALSE(c.compareAndSwap("/cas", v1->mod_revision + 1, "future"));
  EXPECT_TRUE(c.compareAndSwap("/cas", v1->mod_revision, "v2"));
  EXPECT_FALSE(c.compareAndSwap("/cas", v1->mod_revision, "v2 again"));  // now stale
  auto v2 = c.get("/cas");
  EXPECT_EQ(v2->value, "v2");
  EXPECT_FALSE(c.deleteIf("/cas", v1->mod_revision));
  EXPECT_TRUE(c.get("/cas").has_value());
  EXPECT_TRUE(c.deleteIf("/cas", v2->mod_revision));
  EXPECT_FALSE(c.get("/cas").has_value());

  // two writers racing from the same revision: exactly one wins
  c.put("/race", "0");
  const auto rev = c.get("/race")->mod_revision;
  int wins = 0;
  std::vector<std::thread> writers;
  std::atomic<int> won{0};
  for (int i = 0; i < 4; ++i)
    writers.emplace_back([&, i] {
      EtcdClient own({etcd.endpoint()});
      if (own.compareAndSwap("/race", rev, "writer " + std::to_string(i))) ++won;
    });
  for (auto& t : writers) t.join();
  wins = won.load();
  EXPECT_EQ(wins, 1);
}

TEST(EtcdClient, TxnReadsInTheBranchTaken) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  c.put("/x/1", "a");
  c.put("/x/2", "b");
  auto r = c.txn({Compare::valueIs("/x/1", Compare::Result::Equal, "nope")}, {Op::put("/x/3", "c")},
                 {Op::getPrefix("/x/"), Op::get("/x/2")});
  EXPECT_FALSE(r.succeeded);
  ASSERT_EQ(r.reads.size(), 2u);
  EXPECT_EQ(r.reads[0].size(), 2u);
  EXPECT_EQ(r.reads[1].at(0).value, "b");
  EXPECT_FALSE(c.get("/x/3").has_value());
  r = c.txn({Compare::valueIs("/x/1", Compare::Result::Equal, "a"), Compare::version("/x/2", Compare::Result::Greater, 0)},
            {Op::put("/x/3", "c"), Op::del("/x/1")});
  EXPECT_TRUE(r.succeeded);
  EXPECT_EQ(c.get("/x/3")->value, "c");
  EXPECT_FALSE(c.get("/x/1").has_value());
}

TEST(EtcdClient, ALeasedKeyVanishesAfterItsHolderStopsRenewing) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  auto lease = c.leaseGrant(1);
  EXPECT_GE(lease.ttl_s, 1);  // etcd raises small asks to its minimum (2 s with the default election timeout)
  lease = c.leaseGrant(2);
  EXPECT_EQ(lease.ttl_s, 2);
  c.put("/lease/k", "v", lease.id);
  EXPECT_EQ(c.get("/lease/k")->lease, lease.id);
  // renewed every 0.5 s for twice the TTL: still there
  auto renewed = Clock::now();
  for (auto start = Clock::now(); secondsSince(start) < 2.0 * lease.ttl_s;) {
    EXPECT_GT(c.leaseKeepAliveOnce(lease.id), 0);
    renewed = Clock::now();
    std::this_thread::sleep_for(500ms);
  }
  EXPECT_GT(c.leaseKeepAliveOnce(lease.id), 0);
  renewed = Clock::now();
  ASSERT_TRUE(c.get("/lease/k").has_value()) << "present while renewed";
  // no more renewals: gone within TTL + 2 s
  double gone_after = -1;
  while (secondsSince(renewed) < lease.ttl_s + 2.0) {
    if (!c.get("/lease/k").has_value()) {
      gone_after = secondsSince(renewed);
      break;
    }
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_GE(gone_after, 0) << "the key outlived its lease by more than 2 s";
  EXPECT_GE(gone_after, 0.5) << "gone long before the TTL: the lease did not hold it";
  std::printf("lease TTL %lld s: key gone %.2f s after the last renewal\n", static_cast<long long>(lease.ttl_s),
              gone_after);
  EXPECT_EQ(c.leaseKeepAliveOnce(lease.id), 0);  // expired
  // a revoked lease takes its keys at once
  auto other = c.leaseGrant(30);
  c.put("/lease/r1", "1", other.id);
  c.put("/lease/r2", "2", other.id);
  c.leaseRevoke(other.id);
  EXPECT_TRUE(c.range("/lease/").empty());
  EXPECT_EQ(c.leaseKeepAliveOnce(other.id), 0);
  EXPECT_NO_THROW(c.leaseRevoke(other.id));  // already gone: not an error
}

TEST(EtcdClient, LeaseTimeToLiveTellsWhatIsLeftWithoutRenewing) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  auto lease = c.leaseGrant(10);
  c.put("/ttl/a", "1", lease.id);
  c.put("/ttl/b", std::string("\0", 1), lease.id);
  auto info = c.leaseTimeToLive(lease.id, true);
  EXPECT_TRUE(info.alive());
  EXPECT_EQ(info.granted_ttl_s, 10);
  EXPECT_GT(info.ttl_s, 5);
  EXPECT_LE(info.ttl_s, 10);
  ASSERT_EQ(info.keys.size(), 2u);
  std::sort(info.keys.begin(), info.keys.end());
  EXPECT_EQ(info.keys[0], "/ttl/a");
  EXPECT_TRUE(c.leaseTimeToLive(lease.id).keys.empty());  // not asked for
  c.leaseRevoke(lease.id);
  EXPECT_FALSE(c.leaseTimeToLive(lease.id).alive());
  EXPECT_FALSE(c.leaseTimeToLive(123456789).alive());
}

TEST(EtcdClient, ErrorsNameTheEndpointAndTheReason) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  try {
    c.put("/k", "v", 123456789);  // no such lease
    FAIL() << "put with an unknown lease succeeded";
  } catch (const EtcdError& e) {
    EXPECT_EQ(e.endpoint(), etcd.endpoint());
    EXPECT_FALSE(e.transport());
    EXPECT_NE(e.reason().find("lease not found"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(etcd.endpoint()), std::string::npos) << e.what();
  }
  EtcdClient dead({test::deadEndpoint()});
  try {
    dead.get("/k");
    FAIL() << "a dead endpoint answered";
  } catch (const EtcdError& e) {
    EXPECT_TRUE(e.transport());
    EXPECT_EQ(e.endpoint(), test::deadEndpoint());
    EXPECT_NE(e.reason().find("refused"), std::string::npos) << e.what();
  }
}

// A listening socket that never accepts nor answers: connections succeed
// (the kernel's backlog), requests time out.
struct SilentListener {
  int fd = -1;
  int port = 0;
  SilentListener() {
    fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    listen(fd, 16);
    socklen_t n = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    port = ntohs(a.sin_port);
  }
  ~SilentListener() { close(fd); }
  std::string endpoint() const { return "http://127.0.0.1:" + std::to_string(port); }
};

TEST(EtcdClient, TriesTheNextEndpointOnRefusalOrTimeoutAndIsBounded) {
  EtcdProcess etcd;
  SilentListener silent;
  EtcdClient::Options options{std::chrono::milliseconds(300)};
  EtcdClient c({test::deadEndpoint(), silent.endpoint(), etcd.endpoint()}, options);
  auto t0 = Clock::now();
  c.put("/k", "v");  // refused, timed out, then answered
  EXPECT_EQ(c.get("/k")->value, "v");
  // bounded: the silent endpoint's attempt times out (said below) instead of
  // waiting for an answer that never comes. The time is printed; the
  // ceiling only catches a wait without a bound (a loaded or sanitized
  // machine takes several times the 3 x 300 ms)
  std::printf("put and get past a refusing and a silent endpoint: %.3f s\n", secondsSince(t0));
  EXPECT_LT(secondsSince(t0), 30.0);

  // every endpoint down: an error listing each, within the bound
  etcd.kill();
  t0 = Clock::now();
  try {
    c.get("/k");
    FAIL() << "answered with every endpoint down";
  } catch (const EtcdError& e) {
    EXPECT_TRUE(e.transport());
    std::string what = e.what();
    EXPECT_NE(what.find(test::deadEndpoint()), std::string::npos) << what;
    EXPECT_NE(what.find(silent.endpoint() + ": waiting for the answer: timeout"), std::string::npos) << what;
    EXPECT_NE(what.find(etcd.endpoint()), std::string::npos) << what;
  }
  std::printf("every endpoint down: the error after %.3f s (3 endpoints x 300 ms)\n", secondsSince(t0));
  EXPECT_LT(secondsSince(t0), 30.0) << "3 endpoints x 300 ms: bounded";
  // back: the same client works again
  etcd.start();
  EXPECT_EQ(c.get("/k")->value, "v");
}

TEST(EtcdClient, ManyThreadsShareOneClient) {
  EtcdProcess etcd;
  EtcdClient c({etcd.endpoint()});
  std::vector<std::thread> threads;
  std::atomic<int> failures{0};
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 20; ++i) {
        std::string key = "/mt/" + std::to_string(t) + "/" + std::to_string(i);
        try {
          c.put(key, key);
          if (c.get(key)->value != key) ++failures;
        } catch (const std::exception&) {
          ++failures;
        }
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(c.range("/mt/").size(), 160u);
}

}  // namespace
}  // namespace groundsim::fleet
