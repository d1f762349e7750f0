#include "hosted.hpp"

#include "pacing.hpp"
#include "token.hpp"

namespace groundsim::session {

bool HostedSession::tokenMatches(const std::string& token) const { return tokensEqual(token, token_); }

void HostedSession::touch(TimePoint now) {
  std::lock_guard<std::mutex> lk(activity_mutex_);
  last_activity_ = now;
}

double HostedSession::idleSeconds(TimePoint now) const {
  std::lock_guard<std::mutex> lk(activity_mutex_);
  return seconds(now - last_activity_);
}

SessionInfo HostedSession::info(TimePoint now) const {
  SessionInfo i = listing();
  i.idle_s = idleSeconds(now);
  i.epoch = epoch();
  return i;
}

OwnerCheck checkOwner(const HostedSession* s, const std::string& session_id, const std::string& token) {
  if (!s) return {ErrorCode::UnknownSession, "unknown session '" + session_id + "'"};
  if (s->tokenMatches(token)) return {};
  if (token.empty())
    return {ErrorCode::Unauthorized, "session " + session_id + " needs its token (from the create reply)"};
  return {ErrorCode::Unauthorized, "wrong token for session " + session_id};
}

}  // namespace groundsim::session
