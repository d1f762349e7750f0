// The recorder's ledger: every seq from the first owed to the newest known
// is in exactly one of received, repaired, missing and lost.
#include <gtest/gtest.h>

#include <random>

#include "record/ledger.hpp"

namespace groundsim::record {
namespace {

TEST(SeqRanges, AddMergesAndRemoveSplits) {
  SeqRanges r;
  r.add(5, 9);
  r.add(0, 3);
  r.add(4, 4);  // joins both
  EXPECT_EQ(r.text(), "0-9");
  r.remove(3, 5);
  EXPECT_EQ(r.text(), "0-2,6-9");
  r.add(20, 20);
  r.remove(0, 100);
  EXPECT_EQ(r.count(), 0);
  // against a plain set, at random
  std::mt19937 rng(3);
  std::vector<bool> truth(200, false);
  for (int k = 0; k < 2000; ++k) {
    const int a = static_cast<int>(rng() % 200), b = std::min(199, a + static_cast<int>(rng() % 12));
    if (rng() % 2) {
      r.add(a, b);
      for (int i = a; i <= b; ++i) truth[i] = true;
    } else {
      r.remove(a, b);
      for (int i = a; i <= b; ++i) truth[i] = false;
    }
  }
  std::int64_t n = 0;
  for (int i = 0; i < 200; ++i) {
    EXPECT_EQ(r.contains(i), truth[i]) << i;
    n += truth[i];
  }
  EXPECT_EQ(r.count(), n);
  // ranges are disjoint and not adjacent
  std::int64_t prev = -10;
  for (const auto& [a, b] : r.ranges()) {
    EXPECT_GT(a, prev + 1);
    prev = b;
  }
}

void expectPartition(const Ledger& l) {
  const std::int64_t span = l.newest() - l.first() + 1;
  EXPECT_EQ(l.received().count() + l.repaired().count() + l.missing().count() + l.lost().count(), span);
}

TEST(Ledger, GapsBecomeMissingThenRepairedOrLost) {
  Ledger l;
  l.owe(0);
  for (int s : {0, 1, 2, 5, 6, 9}) EXPECT_TRUE(l.arrive(s, false));
  EXPECT_EQ(l.missing().text(), "3-4,7-8");
  expectPartition(l);
  EXPECT_TRUE(l.arrive(4, true));
  EXPECT_FALSE(l.arrive(4, true));  // duplicate
  EXPECT_FALSE(l.arrive(5, false));
  EXPECT_EQ(l.duplicates(), 2);
  l.lose(7, 8);
  EXPECT_EQ(l.missing().text(), "3");
  EXPECT_EQ(l.lost().text(), "7-8");
  l.reach(12);  // a heartbeat says 12 was published
  EXPECT_EQ(l.missing().text(), "3,10-12");
  expectPartition(l);
  l.loseMissing();
  EXPECT_EQ(l.lost().text(), "3,7-8,10-12");
  EXPECT_EQ(l.repaired().text(), "4");
  expectPartition(l);
}

TEST(Ledger, NotOwedBeforeTheFirstHeardAndLostThatTurnsUpIsReceived) {
  Ledger l;
  EXPECT_TRUE(l.arrive(100, false));  // joined late: 0..99 are before the recording
  EXPECT_EQ(l.first(), 100);
  EXPECT_FALSE(l.arrive(50, true));
  EXPECT_TRUE(l.arrive(103, false));
  l.lose(101, 101);
  EXPECT_TRUE(l.arrive(101, true));  // it came after all
  EXPECT_EQ(l.lost().count(), 0);
  EXPECT_EQ(l.missing().text(), "102");
  expectPartition(l);
}

TEST(Ledger, RandomLossAndRepairKeepsThePartition) {
  std::mt19937 rng(11);
  Ledger l;
  l.owe(0);
  std::vector<int> dropped;
  for (int s = 0; s < 5000; ++s) {
    if (rng() % 10 == 0) dropped.push_back(s);
    else l.arrive(s, false);
    if (rng() % 50 == 0 && !dropped.empty()) {
      l.arrive(dropped.back(), true);
      dropped.pop_back();
    }
  }
  expectPartition(l);
  EXPECT_EQ(l.missing().count(), static_cast<std::int64_t>(dropped.size()));
}

}  // namespace
}  // namespace groundsim::record
