// What a standby holds of another server's applied-command log for one
// session (docs/fleet.md, "Sessions that survive their host"): the entries
// from the newest snapshot on, by seq. Entries travel as datagrams; one
// lost is a command the owner acknowledged that a takeover would not
// replay. The gaps are asked for again from the owner's resend ring while
// the owner lives, as the frames the entries were kept with (a recorder
// asks for its missing entries the same way), and a takeover replays only
// the entries that follow the snapshot without a gap.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

#include "stepping/applied.hpp"

namespace groundsim::net {

class StandbyLog {
 public:
  // Missing entries [first_seq, last_seq], and the frames to ask for: from
  // the frame of the entry before the gap (or the snapshot's) to the frame
  // of the entry after it.
  struct Gap {
    std::int64_t first_seq = 0, last_seq = 0;
    std::int64_t from_frame = 0, to_frame = 0;
  };

  StandbyLog() = default;
  explicit StandbyLog(std::size_t max_entries) : max_entries_(max_entries) {}

  // A snapshot taken after `applied_seq` entries, at frame `frame_seq`:
  // the entries before it are in it.
  void rebase(std::int64_t applied_seq, std::int64_t frame_seq);
  // A new owner (a higher epoch): its log goes on from where it resumed,
  // which its first snapshot tells; what the old owner sent is dropped.
  void restart();
  // An entry heard (live or resent): kept unless the snapshot holds it.
  void add(const stepping::Applied& a);
  std::vector<Gap> gaps() const;
  // The entries a takeover replays: from the snapshot's on, up to the first gap.
  std::vector<stepping::Applied> replayable() const;
  std::size_t size() const { return entries_.size(); }
  std::int64_t base() const { return base_; }

 private:
  std::size_t max_entries_ = 1 << 16;
  // a session's log starts at entry 0 with its frame 0; after a new
  // owner's arrival nothing is known until its snapshot
  bool based_ = true;
  std::int64_t base_ = 0, base_frame_ = 0;
  std::map<std::int64_t, stepping::Applied> entries_;
};

}  // namespace groundsim::net
