#include "record/ledger.hpp"

#include <algorithm>
#include <iterator>

namespace groundsim::record {

void SeqRanges::add(std::int64_t first, std::int64_t last) {
  if (last < first) return;
  // merge with a range that ends at or after first - 1 and starts at or before last + 1
  auto it = r_.upper_bound(first);
  if (it != r_.begin() && std::prev(it)->second >= first - 1) --it;
  while (it != r_.end() && it->first <= last + 1) {
    first = std::min(first, it->first);
    last = std::max(last, it->second);
    it = r_.erase(it);
  }
  r_.emplace(first, last);
}

void SeqRanges::remove(std::int64_t first, std::int64_t last) {
  if (last < first) return;
  auto it = r_.upper_bound(first);
  if (it != r_.begin()) --it;
  while (it != r_.end() && it->first <= last) {
    const std::int64_t a = it->first, b = it->second;
    if (b < first) {
      ++it;
      continue;
    }
    it = r_.erase(it);
    if (a < first) r_.emplace(a, first - 1);
    if (b > last) {
      r_.emplace(last + 1, b);
      break;
    }
  }
}

bool SeqRanges::contains(std::int64_t seq) const {
  auto it = r_.upper_bound(seq);
  return it != r_.begin() && std::prev(it)->second >= seq;
}

std::int64_t SeqRanges::count() const {
  std::int64_t n = 0;
  for (const auto& [a, b] : r_) n += b - a + 1;
  return n;
}

std::string SeqRanges::text(std::size_t max_ranges) const {
  std::string out;
  std::size_t k = 0;
  for (const auto& [a, b] : r_) {
    if (k == max_ranges) {
      out += ",... (" + std::to_string(r_.size() - k) + " more ranges)";
      break;
    }
    if (k++) out += ',';
    out += std::to_string(a);
    if (b != a) out += "-" + std::to_string(b);
  }
  return out;
}

void Ledger::owe(std::int64_t first) {
  if (first_ >= 0) return;
  first_ = first;
  newest_ = first - 1;
}

void Ledger::oweFrom(std::int64_t first) {
  if (first_ < 0) return owe(first);
  if (first >= first_) return;
  missing_.add(first, first_ - 1);
  first_ = first;
}

bool Ledger::arrive(std::int64_t seq, bool repaired) {
  if (first_ < 0) owe(seq);
  if (seq < first_ || received_.contains(seq) || repaired_.contains(seq)) {
    ++duplicates_;
    return false;
  }
  if (seq > newest_ + 1) missing_.add(newest_ + 1, seq - 1);
  newest_ = std::max(newest_, seq);
  missing_.remove(seq, seq);
  // a seq declared lost that turns up after all is not lost
  lost_.remove(seq, seq);
  (repaired ? repaired_ : received_).add(seq, seq);
  return true;
}

void Ledger::reach(std::int64_t last) {
  if (first_ < 0 || last <= newest_) return;
  missing_.add(newest_ + 1, last);
  newest_ = last;
}

void Ledger::lose(std::int64_t first, std::int64_t last) {
  // only what is missing can be lost
  for (auto [a, b] : std::map<std::int64_t, std::int64_t>(missing_.ranges())) {
    const std::int64_t lo = std::max(a, first), hi = std::min(b, last);
    if (lo > hi) continue;
    missing_.remove(lo, hi);
    lost_.add(lo, hi);
  }
}

void Ledger::loseMissing() {
  for (const auto& [a, b] : missing_.ranges()) lost_.add(a, b);
  missing_ = SeqRanges();
}

std::string Ledger::summary() const {
  const auto part = [](const char* name, const SeqRanges& r) {
    const std::int64_t n = r.count();
    return std::string(name) + " " + std::to_string(n) + (n ? " (" + r.text(8) + ")" : "");
  };
  return part("received", received_) + ", " + part("repaired", repaired_) + ", " + part("lost", lost_) + ", " +
         part("missing", missing_) + (duplicates_ ? ", duplicates " + std::to_string(duplicates_) : "");
}

}  // namespace groundsim::record
