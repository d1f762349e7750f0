// Every reply and event of the session layer is built here, for the service
// (creates, lookups, refusals) and for sessions (their own requests), so a
// refusal always carries the same fields: a reply with ok = false and the
// code, plus an error event with the same request id.
#pragma once

#include <optional>
#include <string>

#include "types.hpp"

namespace groundsim::session {

inline ReplyTo replyTo(const Request& r) { return ReplyTo{r.op, r.request_id, r.client_id}; }

// A reply addressed to `to`, carrying the session id (may be "").
Reply makeReply(const ReplyTo& to, const std::string& session_id, bool ok, ErrorCode code = ErrorCode::None,
                std::string error = {});
// A vectorised request's refusal: ok false, the code, the field at fault
// and the whole error text, addressed to the request's client.
VecReply refusedVecReply(const VecRequest& r, const std::string& session_id, ErrorCode code, std::string field,
                         std::string error);
// The event that accompanies a refusal of `to`.
Event refusalEvent(const ReplyTo& to, const std::string& session_id, ErrorCode code, const std::string& error,
                   double t = 0.0);
// An event not tied to a request (divergence, timeouts, stops, bad input).
Event sessionEvent(const std::string& session_id, Severity severity, ErrorCode code, std::string reason,
                   double t = 0.0);

// Publishes the refusal event, then the reply (state and t filled in by the caller when known).
void refuse(Output& out, Reply reply);

}  // namespace groundsim::session
