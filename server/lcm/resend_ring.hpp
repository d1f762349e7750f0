// What the server published recently, kept for recorders that missed some
// of it (docs/logging.md, gap repair; as Nasdaq's MoldUDP64 re-request
// server): per session its last frames (state_t and, with the same seq,
// car_state_t and contact_state_t) as encoded bytes, and the server-wide
// events. Bounded in memory (frames and bytes per session, sessions,
// events) and in what it sends (a token bucket per client, in messages
// and bytes per second), so a misbehaving recorder cannot hurt the server.
// Plain bytes, no LCM: the adapter encodes and publishes.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

namespace groundsim::net {

struct ResendLimits {
  int frames_per_session = 4096;          // 2 s at 2 kHz
  std::size_t bytes_per_session = 4 << 20;
  int sessions = 1024;                    // rings kept; the least recently written goes first
  int events = 8192;
  double messages_per_s = 20000;          // per client
  double bytes_per_s = 16e6;              // per client
  double burst_s = 0.5;                   // bucket depth, in seconds of the rates
  int clients = 256;                      // buckets kept; the least recently used goes first
  double linger_s = 120;                  // a ring not written for this long is dropped
};

class ResendRing {
 public:
  using Clock = std::chrono::steady_clock;
  // the values of resent_t's STATUS_* (lcmtypes/resent_t.lcm)
  enum class Status : std::int8_t { Ok = 0, Gone = 1, Limited = 2, UnknownSession = 3, Elsewhere = 4 };
  struct Message {
    Status status = Status::Ok;
    std::int64_t seq = 0, last_seq = 0;   // Ok: last_seq == seq; else the range
    std::string channel;                  // Ok only
    std::vector<std::uint8_t> bytes;      // Ok only
  };
  struct Stats {
    std::int64_t requests = 0, resent = 0, gone = 0, limited = 0, unknown = 0, elsewhere = 0;
    std::size_t bytes_held = 0;
    int sessions = 0;
  };

  // Who asks the ring: the session's owner speaks for all of it (what it
  // kept unsent while fenced, and Gone or UnknownSession for what it does
  // not hold); a server that published some of a session before it moved
  // (or while its lease is in doubt) answers only the messages it sent, and
  // is silent on the rest, which the owner speaks for.
  enum class Scope { Owner, Published };

  explicit ResendRing(ResendLimits limits = {}) : limits_(limits) {}

  // One message of a session's frame `seq` (a frame may be several messages
  // on several channels, added in order) or an event; `sent` false: kept
  // while fenced, not published.
  void addFrame(const std::string& session, std::int64_t seq, const std::string& channel, const std::uint8_t* data,
                std::size_t size, bool sent = true, Clock::time_point now = Clock::now());
  void addEvent(std::int64_t seq, const std::string& channel, const std::uint8_t* data, std::size_t size);

  // What to send a client asking for [from, to] (to < 0: up to the newest)
  // of a session's frames (session non-empty) or of the events (session
  // empty): held messages in seq order while the client's bucket allows,
  // then one Limited range for the rest; a Gone range for seqs older than
  // the ring, an Elsewhere range for those before the first seq this server
  // published of the session (it took the session over at that seq: an
  // earlier owner published them); UnknownSession when no ring is kept for
  // it. Scope::Published: the sent messages held, in the same order and
  // bucket, and nothing else.
  std::vector<Message> answer(const std::string& client, const std::string& session, std::int64_t from,
                              std::int64_t to, Scope scope = Scope::Owner, Clock::time_point now = Clock::now());

  // Drops rings not written for linger_s.
  void expire(Clock::time_point now = Clock::now());
  Stats stats() const;

 private:
  struct Held {
    std::int64_t seq;
    std::string channel;
    std::vector<std::uint8_t> bytes;
    bool sent = true;
  };
  struct Ring {
    std::deque<Held> held;
    std::int64_t first = -1;  // the first seq added here
    std::size_t bytes = 0;
    Clock::time_point written;
  };
  struct Bucket {
    double messages = 0, bytes = 0;
    Clock::time_point filled, used;
  };
  void push(Ring& r, Held h, std::size_t max_bytes, std::size_t max_messages);
  Bucket& bucket(const std::string& client, Clock::time_point now);
  std::vector<Message> collect(Ring& r, const std::string& client, std::int64_t from, std::int64_t to, Scope scope,
                               Clock::time_point now);

  ResendLimits limits_;
  std::map<std::string, Ring> sessions_;
  Ring events_;
  std::map<std::string, Bucket> buckets_;
  Stats stats_;
};

}  // namespace groundsim::net
