// The core of `groundsim record` (docs/logging.md): what arrives from the
// bus goes into an MCAP file, one chunk group per session (a reader of one
// session reads only its chunks); a ledger per session and one for the
// server's events account for every seq; gaps are asked for again
// (resend_t) with backoff, and what the server no longer holds, or never
// answers, is lost with its range named, in the file and on stderr.
// No LCM here: the command feeds datagrams in and sends what request()
// returns, so the logic is tested without a network.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <groundsim/resend_t.hpp>
#include <groundsim/resent_t.hpp>

#include "record/ledger.hpp"
#include "recording/mcap_writer.hpp"

namespace groundsim::record {

struct RecorderOptions {
  bool raw = false;               // also keep each message's LCM bytes (channels "lcm/<LCM channel>")
  double first_ask_s = 0.05;      // a gap is asked for this long after it is seen (reordering settles)
  double retry_s = 0.25;          // then again after retry_s, 2 retry_s, 4 retry_s ...
  int asks = 6;                   // ... this many times, then its seqs are lost
  double limited_retry_s = 0.2;   // the server said "over your rate": ask again after this
  std::int64_t max_ask = 4096;    // seqs per resend_t
};

class Recorder {
 public:
  using Clock = std::chrono::steady_clock;
  Recorder(std::unique_ptr<recording::McapWriter> out, std::string client_id, RecorderOptions o = {});
  ~Recorder();

  // Sessions to record. created: the recording saw it begin (seq 0 is owed).
  void add(const std::string& session, bool created);
  bool has(const std::string& session) const { return sessions_.count(session) > 0; }
  // A file the session's scenario names (the recorder created it and sent
  // it): attached as assets/<session>/<name>, for re-simulation.
  void addAsset(const std::string& session, const std::string& name, std::shared_ptr<const std::string> bytes);

  // A datagram from the bus (state, car state, contact, event, scenario,
  // a player's commands). Returns false when it could not be decoded or its
  // seq is outside [0, 2^53) (counted, never written).
  bool onDatagram(const std::string& channel, const std::uint8_t* data, int size);
  // The server's answer to a re-request.
  void onResent(const groundsim::resent_t& m, Clock::time_point now);
  // The heartbeat lists a session with its newest seq: owed up to there.
  void onHeartbeat(const std::string& session, std::int64_t last_seq, bool final, Clock::time_point now);
  // The re-requests due now.
  std::vector<groundsim::resend_t> requests(Clock::time_point now);
  // Asks for the tail (everything after the newest arrived) of every session.
  std::vector<groundsim::resend_t> tailRequests(Clock::time_point now);
  // Whether a repair is still outstanding.
  bool repairing() const;
  // Ends the recording: every missing seq becomes lost; the ledgers go into
  // the file as metadata; the summary and footer are written.
  void finish();
  // Closes the current file (with the ledgers as they stand) and goes on in
  // `next`: the schemas, every session's channels and scenario again, so
  // each part reads on its own. Ledgers and repairs carry over.
  void rotate(std::unique_ptr<recording::McapWriter> next);
  std::uint64_t bytesWritten() const;
  int part() const { return part_; }

  struct Totals {
    std::int64_t received = 0, repaired = 0, lost = 0, missing = 0, duplicates = 0, undecodable = 0;
    std::int64_t asked = 0, resent_bytes = 0, live_bytes = 0;
  };
  Totals totals() const;
  // One line per session and one for events: the ledger's summary.
  std::vector<std::string> report() const;
  bool ended(const std::string& session) const;
  bool allEnded() const;

 private:
  struct Gap {
    Clock::time_point due;
    int asks = 0;
    bool elsewhere = false;  // the owner said an earlier owner published it (printed once)
  };
  struct Stream {
    std::string id;                      // session id ("" for the events)
    // a frame's messages: the state, and (once one was heard: the session
    // has road cars, objects or collisions) the car state and the contact
    // state of the same seq; the events' stream uses `ledger` alone
    Ledger ledger, car, contact;
    std::map<std::int64_t, Gap> asking;  // first seq of a missing range -> when to ask
    bool ended = false;
    int group = 0;
    std::uint16_t state_ch = 0, car_ch = 0, contact_ch = 0, events_ch = 0;  // MCAP channels
    std::uint16_t drive_ch = 0, controls_ch = 0;  // players' commands as heard (no token)
    // the session's applied-command log (applied_t): its own seqs, each
    // entry kept by the server with a frame (frame_seq), so a gap is asked
    // for as the frames around it; every ending frame (status finished,
    // stopped, diverged) carries an END entry, owed until it arrives
    Ledger applied;
    std::uint16_t applied_ch = 0;
    std::map<std::int64_t, std::int64_t> applied_frame;  // entry seq -> frame_seq (arrived entries)
    std::map<std::int64_t, Gap> asking_applied;          // first entry seq of a missing range -> when to ask
    std::set<std::int64_t> end_frames;                   // frame seqs whose END entry arrived
    std::map<std::int64_t, Gap> end_owed;                // ending frames heard without their END entry
    std::set<std::int64_t> end_missing;                  // ... never came after every ask
    // protocol 2: the newest owner's epoch heard; a message of a lower one
    // (a fenced old owner's, docs/protocol.md) is counted, not written
    std::int64_t epoch = 0, fenced = 0;
    // the lowest frame seq heard at `epoch`: an earlier owner's message of a
    // lower seq was published before the move (an answer to a re-request of
    // what the new owner does not hold) and is written
    std::int64_t epoch_from = -1;
    // A failover: the new owner publishes again the seqs from its snapshot
    // on (docs/fleet.md). Those up to the highest seq heard when the epoch
    // rose are counted as re-simulated, not repeats (the first kept).
    std::int64_t top = -1, moved_at = -1, resimulated = 0;
    std::int64_t live_seq = -1, live_utime = 0;   // the newest state heard live
    std::string scenario;  // the scenario's JSON, once heard
    std::vector<std::pair<std::string, std::shared_ptr<const std::string>>> assets;  // by name
  };
  Stream& stream(const std::string& session);
  void write(Stream& s, std::uint16_t channel, std::int64_t seq, std::int64_t utime, const std::string& json,
             const std::string& lcm_channel, const std::uint8_t* data, int size);
  // a datagram heard (repaired: resent); false when it does not decode.
  // Its steps, one a kind of channel:
  bool handle(const std::string& channel, const std::uint8_t* data, int size, bool repaired);
  bool handleState(const std::string& channel, const std::uint8_t* data, int size, bool repaired);
  template <class Msg>  // car state, contact state
  bool handleCompanion(const char* type, Ledger Stream::*ledger, std::uint16_t Stream::*ch,
                       const std::string& channel, const std::uint8_t* data, int size, bool repaired);
  bool handleApplied(const std::string& channel, const std::uint8_t* data, int size, bool repaired);
  bool handleEvent(const std::string& channel, const std::uint8_t* data, int size, bool repaired);
  bool handleCommand(const std::string& channel, const std::uint8_t* data, int size);  // drive, controls
  bool handleScenario(const std::uint8_t* data, int size);
  // a frame's car state or contact state, with its own ledger
  template <class Msg>
  void companion(Stream& s, Ledger& l, std::uint16_t ch, const Msg& m, const std::string& channel,
                 const std::uint8_t* data, int size, bool repaired);
  void prepare();
  void channels(Stream& s);
  void writeLedgers();
  SeqRanges missing(const Stream& s) const;
  void lose(Stream& s, std::int64_t first, std::int64_t last);
  void ask(Stream& s, std::int8_t stream, Clock::time_point now, std::vector<groundsim::resend_t>& out);
  void askApplied(Stream& s, Clock::time_point now, std::vector<groundsim::resend_t>& out);
  void appliedOwed(Stream& s);  // the applied ledger starts where the state ledger does
  // true: of a lower epoch than heard and not before the newest epoch's
  // first seq (a fenced owner's), counted
  bool fencedOff(Stream& s, std::int64_t epoch, std::int64_t seq);
  std::uint16_t rawChannel(const std::string& lcm_channel);

  std::unique_ptr<recording::McapWriter> out_;
  std::string client_id_;
  RecorderOptions o_;
  std::map<std::string, Stream> sessions_;
  Stream events_;
  std::uint16_t state_schema_ = 0, car_schema_ = 0, contact_schema_ = 0, event_schema_ = 0;
  std::uint16_t drive_schema_ = 0, controls_schema_ = 0, applied_schema_ = 0;
  std::map<std::string, std::uint16_t> raw_channels_;
  std::int64_t request_seq_ = 0;
  Totals counts_;
  bool finished_ = false;
  int part_ = 0;
};

}  // namespace groundsim::record
