// The account a recorder keeps of one stream (a session's frames, or the
// server's events): which seqs arrived live, which were repaired (resent
// by the server on request), which were lost for good, and which are
// missing and still being asked for. Nothing is lost silently: every seq
// from the first one owed to the newest one known is in exactly one of
// received, repaired, missing or lost.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace groundsim::record {

// Disjoint closed ranges [first, last] of seqs.
class SeqRanges {
 public:
  void add(std::int64_t first, std::int64_t last);
  void remove(std::int64_t first, std::int64_t last);
  bool contains(std::int64_t seq) const;
  std::int64_t count() const;
  const std::map<std::int64_t, std::int64_t>& ranges() const { return r_; }
  // "0-99,102,110-200"
  std::string text(std::size_t max_ranges = 64) const;

 private:
  std::map<std::int64_t, std::int64_t> r_;  // first -> last
};

class Ledger {
 public:
  // The first seq owed: 0 when the recording saw the stream begin,
  // else the first heard (the ones before are "before the recording").
  void owe(std::int64_t first);
  // Owed from an earlier seq after all (the stream turned out to have begun
  // while the recorder listened): seqs from `first` to the first owed
  // before become missing.
  void oweFrom(std::int64_t first);
  // A seq arrived (live or repaired). Returns false for a duplicate.
  // Seqs skipped between the newest known and this one become missing.
  bool arrive(std::int64_t seq, bool repaired);
  // The stream is known to reach `last` (a heartbeat, an end): seqs after
  // the newest arrived, up to last, become missing.
  void reach(std::int64_t last);
  // Missing seqs the server no longer holds: lost for good.
  void lose(std::int64_t first, std::int64_t last);
  // Everything still missing becomes lost (at the end of a recording).
  void loseMissing();

  bool started() const { return first_ >= 0; }
  std::int64_t first() const { return first_; }
  std::int64_t newest() const { return newest_; }
  const SeqRanges& received() const { return received_; }
  const SeqRanges& repaired() const { return repaired_; }
  const SeqRanges& missing() const { return missing_; }
  const SeqRanges& lost() const { return lost_; }
  std::int64_t duplicates() const { return duplicates_; }
  // "received 1000 (0-999), repaired 12 (40-51), lost 0, missing 0"
  std::string summary() const;

 private:
  std::int64_t first_ = -1, newest_ = -1;
  SeqRanges received_, repaired_, missing_, lost_;
  std::int64_t duplicates_ = 0;
};

}  // namespace groundsim::record
