#include "answers.hpp"

#include <cstdint>
#include <utility>

namespace groundsim::session {

namespace {

// What every reply carries, a Reply's or a VecReply's: whom it answers,
// the session, the outcome.
template <class R, class Op>
R addressed(Op op, std::int64_t request_id, const std::string& client_id, const std::string& session_id, bool ok,
            ErrorCode code, std::string error) {
  R r;
  r.op = op;
  r.request_id = request_id;
  r.client_id = client_id;
  r.session_id = session_id;
  r.ok = ok;
  r.code = code;
  r.error = std::move(error);
  return r;
}

}  // namespace

Reply makeReply(const ReplyTo& to, const std::string& session_id, bool ok, ErrorCode code, std::string error) {
  return addressed<Reply>(to.op, to.request_id, to.client_id, session_id, ok, code, std::move(error));
}

VecReply refusedVecReply(const VecRequest& r, const std::string& session_id, ErrorCode code, std::string field,
                         std::string error) {
  VecReply reply = addressed<VecReply>(r.op, r.request_id, r.client_id, session_id, false, code, std::move(error));
  reply.field = std::move(field);
  return reply;
}

Event refusalEvent(const ReplyTo& to, const std::string& session_id, ErrorCode code, const std::string& error,
                   double t) {
  Event e;
  e.session_id = session_id;
  e.client_id = to.client_id;
  e.request_id = to.request_id;
  e.severity = Severity::Error;
  e.code = code;
  e.reason = error;
  e.t = t;
  return e;
}

Event sessionEvent(const std::string& session_id, Severity severity, ErrorCode code, std::string reason, double t) {
  Event e;
  e.session_id = session_id;
  e.severity = severity;
  e.code = code;
  e.reason = std::move(reason);
  e.t = t;
  return e;
}

void refuse(Output& out, Reply reply) {
  out.publishEvent(refusalEvent(ReplyTo{reply.op, reply.request_id, reply.client_id}, reply.session_id, reply.code,
                                reply.error, reply.t));
  out.publishReply(reply);
}

}  // namespace groundsim::session
