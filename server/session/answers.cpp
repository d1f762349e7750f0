#include "answers.hpp"

namespace groundsim::session {

Reply makeReply(const ReplyTo& to, const std::string& session_id, bool ok, ErrorCode code, std::string error) {
  Reply r;
  r.op = to.op;
  r.request_id = to.request_id;
  r.client_id = to.client_id;
  r.session_id = session_id;
  r.ok = ok;
  r.code = code;
  r.error = std::move(error);
  return r;
}

VecReply refusedVecReply(const VecRequest& r, const std::string& session_id, ErrorCode code, std::string field,
                         std::string error) {
  VecReply reply;
  reply.op = r.op;
  reply.request_id = r.request_id;
  reply.client_id = r.client_id;
  reply.session_id = session_id;
  reply.ok = false;
  reply.code = code;
  reply.field = std::move(field);
  reply.error = std::move(error);
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
