// Splitting a vectorised reply into parts that each fit one datagram
// (kMaxVecPartBytes), and putting them back together on the client with an
// account of what is missing. Shared by groundsim-server and every client.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <groundsim/vec_reply_t.hpp>

#include "limits.hpp"

namespace groundsim::net {

// Bytes one environment adds to a part: its observation row, reward, two
// flags, three counters and the divergence flag.
std::size_t vecBytesPerEnv(int obs_size);

// `whole` carries every environment (env_begin 0, env_count num_envs) and
// the whole snapshot. Returns parts 0..n-1 with the same header, each
// encoding to at most max_bytes (a single environment or a header larger
// than that still gets a part of its own: never an empty split). The
// sessions of an OP_CREATE reply ride in part 0.
std::vector<groundsim::vec_reply_t> splitVecReply(const groundsim::vec_reply_t& whole,
                                                  std::size_t max_bytes = kMaxVecPartBytes);

// Collects the parts of one reply (matched by request id and client id by
// the caller). Parts that contradict the first one (other nparts, ranges
// out of bounds or overlapping) are refused with a reason, never merged.
class VecAssembler {
 public:
  explicit VecAssembler(std::int64_t request_id = 0) : request_id_(request_id) {}
  std::int64_t requestId() const { return request_id_; }

  // "" when the part was taken, else why not (duplicate, inconsistent).
  std::string add(const groundsim::vec_reply_t& part);
  bool started() const { return nparts_ > 0; }
  bool complete() const { return nparts_ > 0 && received_ == nparts_; }
  int parts() const { return nparts_; }
  std::vector<int> missing() const;
  // "parts 1, 3 of 4" (or "every part" when none arrived)
  std::string missingText() const;

  // The reassembled reply (complete() only): one vec_reply_t covering every
  // environment and the whole snapshot, part 0, nparts 1.
  groundsim::vec_reply_t take();

 private:
  std::int64_t request_id_;
  int nparts_ = 0;
  int received_ = 0;
  std::vector<std::optional<groundsim::vec_reply_t>> parts_;
};

}  // namespace groundsim::net
