#include "standby_log.hpp"

namespace groundsim::net {

void StandbyLog::rebase(std::int64_t applied_seq, std::int64_t frame_seq) {
  based_ = true;
  base_ = applied_seq;
  base_frame_ = frame_seq;
  entries_.erase(entries_.begin(), entries_.lower_bound(applied_seq));
}

void StandbyLog::restart() {
  based_ = false;
  entries_.clear();
}

void StandbyLog::add(const stepping::Applied& a) {
  if (based_ && a.seq < base_) return;
  // bounded: one snapshot interval's worth is what a takeover replays; past
  // the bound the oldest go (the replay then ends at the gap they leave)
  if (entries_.size() >= max_entries_ && !entries_.count(a.seq)) entries_.erase(entries_.begin());
  entries_[a.seq] = a;
}

std::vector<StandbyLog::Gap> StandbyLog::gaps() const {
  std::vector<Gap> out;
  if (!based_) return out;
  std::int64_t expect = base_, frame = base_frame_;
  for (const auto& [seq, a] : entries_) {
    if (seq > expect) out.push_back(Gap{expect, seq - 1, frame, a.frame_seq});
    expect = seq + 1;
    frame = a.frame_seq;
  }
  return out;
}

std::vector<stepping::Applied> StandbyLog::replayable() const {
  std::vector<stepping::Applied> out;
  if (!based_) return out;
  std::int64_t expect = base_;
  for (const auto& [seq, a] : entries_) {
    if (seq != expect) break;
    out.push_back(a);
    ++expect;
  }
  return out;
}

}  // namespace groundsim::net
