// The LcmServer's input (lcm_server.hpp): the datagrams heard on the
// request, drive, controls, vectorised-request and asset channels, decoded,
// their ids checked and handed to the session service; the resend channel's
// re-requests go to handleResend (lcm_server.cpp), which answers from the
// ring.
#include <exception>
#include <string>
#include <utility>

#include <groundsim/asset_part_t.hpp>
#include <groundsim/resend_t.hpp>

#include "convert.hpp"
#include "fleet_node.hpp"
#include "input_checks.hpp"
#include "latency_trace.hpp"
#include "lcm_server.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "session/answers.hpp"

namespace groundsim::net {

using input_checks::badId;
using input_checks::badIds;
using input_checks::codeFor;

template <class Msg>
bool LcmServer::decoded(Msg& msg, const char* type, const std::string& channel, const void* data, int size) {
  const DecodeResult d = decodeMessage(data, size, msg, type);
  if (!d.ok()) service_->reportBadInput(codeFor(d.status), channel, d.reason);
  return d.ok();
}
// the resend handler (lcm_server.cpp) decodes the same way
template bool LcmServer::decoded(groundsim::resend_t&, const char*, const std::string&, const void*, int);

void LcmServer::onDatagram(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  handleDatagram(channel, rbuf->data, static_cast<int>(rbuf->data_size));
}

// Handlers run inside lcm_handle(), which is C: an exception must stop here
// (as Drake's DrakeLcm stores it) and become an event, never unwind.
void LcmServer::handleDatagram(const std::string& channel, const void* data, int size) noexcept {
  try {
    ++inputs_;
    if (channel == kRequestChannel) handleRequest(channel, data, size);
    else if (channel == kDriveChannel) handleDrive(channel, data, size);
    else if (channel == kControlsChannel) handleControls(channel, data, size);
    else if (channel == kVecRequestChannel) handleVecRequest(channel, data, size);
    else if (channel == kAssetChannel) handleAsset(channel, data, size);
    else if (channel == kResendChannel) handleResend(channel, data, size);
  } catch (const std::exception& e) {
    try {
      service_->reportBadInput(session::ErrorCode::Internal, channel, std::string("internal error: ") + e.what());
    } catch (...) {
    }
  } catch (...) {
    try {
      service_->reportBadInput(session::ErrorCode::Internal, channel, "internal error: unknown exception");
    } catch (...) {
    }
  }
}

void LcmServer::handleRequest(const std::string& channel, const void* data, int size) {
  groundsim::request_t msg;
  if (!decoded(msg, "groundsim.request_t", channel, data, size)) return;
  std::string why = badId("client_id", msg.client_id);
  if (!why.empty()) return service_->reportBadInput(session::ErrorCode::BadRequest, channel, why);
  for (const auto& [field, v] : {std::pair{"session_id", &msg.session_id}, std::pair{"token", &msg.token}})
    if (why.empty()) why = badId(field, *v);
  session::Request r = fromMessage(msg);
  if (!why.empty()) {
    // answerable: the client id is fine, so the client hears why
    session::Reply reply = session::makeReply(session::replyTo(r), "", false, session::ErrorCode::BadRequest, why);
    session::Event e = session::refusalEvent(session::replyTo(r), "", reply.code, why);
    e.channel = channel;
    publishEvent(e);
    publishReply(reply);
    return;
  }
  if (r.op == session::Op::Drain) {
    if (msg.server_id == server_id_) {
      session::Reply ok = session::makeReply(session::replyTo(r), "", true);
      publishReply(ok);
      drain_requested_ = true;
      return;
    }
    if (fleet_) return;  // the server named answers
    const std::string why = "server_id: " + net::quoted(msg.server_id) + " is not this server (" + server_id_ + ")";
    publishReply(session::makeReply(session::replyTo(r), "", false, session::ErrorCode::BadRequest, why));
    return;
  }
  if (fleet_) {
    if (r.op == session::Op::Create) {
      fleet_->onCreate(
          r.client_id, r.request_id, [this, r] { service_->handleRequest(r); },
          [this, r](const std::string& why) {
            publishReply(session::makeReply(session::replyTo(r), "", false, session::ErrorCode::Unavailable, why));
          });
      return;
    }
    if (r.op == session::Op::List) {
      if (!fleet_->isAnswerer()) return;
      session::Reply reply = session::makeReply(session::replyTo(r), "", true);
      reply.sessions = fleet_->fleetSessions(service_->status().sessions);
      publishReply(reply);
      return;
    }
    if (!fleet_->answers(r.session_id, [this, r] { service_->handleRequest(r); })) return;
  }
  service_->handleRequest(r);
}

void LcmServer::handleDrive(const std::string& channel, const void* data, int size) {
  groundsim::drive_t msg;
  if (!decoded(msg, "groundsim.drive_t", channel, data, size)) return;
  if (const std::string why = badIds(msg); !why.empty())
    return service_->reportBadInput(session::ErrorCode::BadControl, channel, "drive: " + why);
  session::Drive drive = fromMessage(msg);
  if (LatencyTrace::on())
    LatencyTrace::line("drx %s %lld %lld", msg.session_id.c_str(), static_cast<long long>(msg.seq),
                       static_cast<long long>(LatencyTrace::us(drive.received)));
  if (fleet_ && !fleet_->answers(drive.session_id, [this, drive] { service_->handleDrive(drive); })) return;
  service_->handleDrive(std::move(drive));
}

void LcmServer::handleControls(const std::string& channel, const void* data, int size) {
  groundsim::controls_t msg;
  if (!decoded(msg, "groundsim.controls_t", channel, data, size)) return;
  if (const std::string why = badIds(msg); !why.empty())
    return service_->reportBadInput(session::ErrorCode::BadControl, channel, "controls: " + why);
  session::CarDrive car = fromMessage(msg);
  if (fleet_ && !fleet_->answers(car.session_id, [this, car] { service_->handleControls(car); })) return;
  service_->handleControls(std::move(car));
}

void LcmServer::handleVecRequest(const std::string& channel, const void* data, int size) {
  groundsim::vec_request_t msg;
  if (!decoded(msg, "groundsim.vec_request_t", channel, data, size)) return;
  std::string why = badId("client_id", msg.client_id);
  if (!why.empty()) return service_->reportBadInput(session::ErrorCode::BadRequest, channel, why);
  std::string field;
  for (const auto& [f, v] : {std::pair{"session_id", &msg.session_id}, std::pair{"token", &msg.token}})
    if (why.empty() && !(why = badId(f, *v)).empty()) field = f;
  session::VecRequest r = fromMessage(msg);
  if (LatencyTrace::on())
    LatencyTrace::line("vreq %s %s %lld %d %lld", msg.client_id.c_str(), msg.session_id.c_str(),
                       static_cast<long long>(msg.request_id), static_cast<int>(msg.op),
                       static_cast<long long>(LatencyTrace::nowUs()));
  if (!why.empty()) {
    // answerable: the client id is fine, so the client hears why
    const session::VecReply reply = session::refusedVecReply(r, "", session::ErrorCode::BadRequest, field, why);
    session::Event e = session::refusalEvent(session::ReplyTo{session::Op::List, r.request_id, r.client_id}, "",
                                             reply.code, why);
    e.channel = channel;
    publishEvent(e);
    publishVecReply(reply);
    return;
  }
  if (fleet_) {
    if (r.op == session::VecOp::Create) {
      fleet_->onCreate(
          r.client_id, r.request_id, [this, r] { service_->handleVecRequest(r); },
          [this, r](const std::string& why) {
            publishVecReply(session::refusedVecReply(r, "", session::ErrorCode::Unavailable, "", why));
          });
      return;
    }
    if (!fleet_->answers(r.session_id, [this, r] { service_->handleVecRequest(r); })) return;
  }
  service_->handleVecRequest(std::move(r));
}

void LcmServer::handleAsset(const std::string& channel, const void* data, int size) {
  groundsim::asset_part_t msg;
  if (!decoded(msg, "groundsim.asset_part_t", channel, data, size)) return;
  std::string why = badId("client_id", msg.client_id);
  if (!why.empty()) return service_->reportBadInput(session::ErrorCode::BadRequest, channel, "asset: " + why);
  if (msg.size < 0)
    return service_->reportBadInput(session::ErrorCode::BadRequest, channel,
                                    "asset: size must be >= 0, got " + std::to_string(msg.size));
  session::AssetPart p;
  p.client_id = std::move(msg.client_id);
  p.name = printable(msg.name, 200);
  p.sha256 = printable(msg.sha256, 80);
  p.size = static_cast<std::uint64_t>(msg.size);
  p.part = msg.part;
  p.nparts = msg.nparts;
  p.data.assign(msg.data.begin(), msg.data.end());
  service_->handleAssetPart(p, channel);
}

}  // namespace groundsim::net
