// libFuzzer target: raw datagrams -> decoding -> the server's request and
// drive handling, in process (what LcmServer::onRequest/onDrive do, without
// the network). One input is a sequence of datagrams (datagram_input.hpp);
// each goes through decodeMessage and, when it decodes, through
// SessionService::handleRequest/handleDrive of a fresh service. A session id
// or token "@" stands for a lockstep session the harness created, so
// mutated steps, drives and controls reach a live session too.
// Findings: a crash, a sanitizer report, a leak, an exception out of the
// service, a request left unanswered (the service answers every request).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>

#include <groundsim/drive_t.hpp>
#include <groundsim/request_t.hpp>

#include "codec.hpp"
#include "convert.hpp"
#include "datagram_input.hpp"
#include "recording_output.hpp"
#include "session/service.hpp"

namespace {

using namespace groundsim;
using fuzz::RecordingOutput;

constexpr const char* kPlaceholder = "@";
constexpr double kReplyWaitSeconds = 5.0;

// The harness's own session, created on the first "@" reference of an input.
const char* kTargetScenario =
    R"({"ground":{"type":"plane"},"physics":{"dt":1e-3},"vehicle":{"initial":{"wheel_spin":5}}})";

class Harness {
 public:
  Harness() : svc_(config(), out_) {}

  void request(session::Request r) {
    substitute(r);
    send(r);
  }
  void drive(session::Drive d) {
    substitute(d);
    svc_.handleDrive(std::move(d));
  }
  void badInput(const char* channel, const std::string& reason) {
    svc_.reportBadInput(session::ErrorCode::Decode, channel, reason);
  }
  // Stops every session (each answers its pending requests), then checks
  // that every request got its reply.
  void finish() {
    svc_.shutdown("fuzz input done");
    if (out_.replies() < requests_) {
      std::fprintf(stderr, "datagram_fuzz: %d requests, %d replies\n", requests_, out_.replies());
      std::abort();
    }
  }

 private:
  static session::ServiceConfig config() {
    session::ServiceConfig cfg;
    cfg.workers = 1;
    cfg.max_sessions = 4;
    return cfg;
  }

  void send(const session::Request& r) {
    svc_.handleRequest(r);
    ++requests_;
    // a create builds on a worker: wait for its answer, so that what follows
    // meets the same registry on every run of this input
    if (r.op == session::Op::Create) out_.waitCreateReplies(++creates_, kReplyWaitSeconds);
  }

  template <class R>
  void substitute(R& r) {
    if (r.session_id != kPlaceholder && r.token != kPlaceholder) return;
    ensureTarget();
    if (r.session_id == kPlaceholder) r.session_id = target_id_;
    if (r.token == kPlaceholder) r.token = target_token_;
  }

  void ensureTarget() {
    if (target_tried_) return;
    target_tried_ = true;
    session::Request c;
    c.op = session::Op::Create;
    c.request_id = -1;
    c.client_id = "fuzz-harness";
    c.scenario_json = kTargetScenario;
    c.mode = static_cast<int>(session::Mode::Lockstep);
    send(c);
    const auto reply = out_.waitReply(c.client_id, c.request_id, kReplyWaitSeconds);
    if (!reply || !reply->ok) {
      std::fprintf(stderr, "datagram_fuzz: the harness's create failed: %s\n",
                   reply ? reply->error.c_str() : "no reply");
      std::abort();
    }
    target_id_ = reply->session_id;
    target_token_ = reply->token;
  }

  RecordingOutput out_;
  session::SessionService svc_;  // after out_: it publishes through it
  int requests_ = 0, creates_ = 0;
  bool target_tried_ = false;
  std::string target_id_, target_token_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Harness h;
  for (const fuzz::Datagram& d : fuzz::splitDatagrams(data, size)) {
    if (d.channel == fuzz::Channel::Request) {
      groundsim::request_t msg;
      const net::DecodeResult r = net::decodeMessage(d.data, d.size, msg, "groundsim.request_t");
      if (r.ok()) h.request(net::fromMessage(msg));
      else h.badInput("GROUNDSIM_REQUEST", r.reason);
    } else {
      groundsim::drive_t msg;
      const net::DecodeResult r = net::decodeMessage(d.data, d.size, msg, "groundsim.drive_t");
      if (r.ok()) h.drive(net::fromMessage(msg));
      else h.badInput("GROUNDSIM_DRIVE", r.reason);
    }
  }
  h.finish();
  return 0;
}
