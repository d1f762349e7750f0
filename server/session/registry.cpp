#include "registry.hpp"

#include <algorithm>

#include "pacing.hpp"
#include "token.hpp"

namespace groundsim::session {

int Registry::heldLocked(const std::string& client) const {
  int n = 0;
  for (const auto& [id, s] : sessions_) n += s->creator() == client;
  auto r = reserved_by_.find(client);
  return n + (r == reserved_by_.end() ? 0 : r->second);
}

OwnerCheck Registry::admit(int max_sessions, const std::string* client, int client_max) {
  std::lock_guard<std::mutex> lk(mutex_);
  if (closed_) return {ErrorCode::Shutdown, "server is shutting down"};
  const int used = static_cast<int>(sessions_.size()) + reserved_;
  if (used >= max_sessions)
    return {ErrorCode::TooManySessions,
            "too many sessions: " + std::to_string(used) + " of " + std::to_string(max_sessions) +
                " in use (stop one, or start the server with a larger --max-sessions)"};
  if (client && client_max > 0) {
    const int held = heldLocked(*client);
    if (held >= client_max)
      return {ErrorCode::TooManySessions,
              "too many sessions for client '" + client->substr(0, 64) + "': it holds " + std::to_string(held) +
                  ", at most " + std::to_string(client_max) +
                  " (server --client-sessions; stop one of its sessions first)"};
  }
  ++reserved_;
  if (client) ++reserved_by_[*client];
  return {};
}

void Registry::cancel(const std::string& id, const std::string* client) {
  std::lock_guard<std::mutex> lk(mutex_);
  if (!id.empty()) pending_ids_.erase(id);
  if (reserved_ > 0) --reserved_;
  if (client) unreserve(*client);
}

std::string Registry::newId() {
  std::lock_guard<std::mutex> lk(mutex_);
  std::string id;
  do id = newSessionId();
  while (sessions_.count(id) || pending_ids_.count(id));
  pending_ids_.insert(id);
  return id;
}

void Registry::cancelId(const std::string& id) {
  std::lock_guard<std::mutex> lk(mutex_);
  pending_ids_.erase(id);
}

void Registry::unreserve(const std::string& client) {
  auto it = reserved_by_.find(client);
  if (it != reserved_by_.end() && --it->second <= 0) reserved_by_.erase(it);
}

void Registry::insert(std::shared_ptr<HostedSession> s) {
  std::lock_guard<std::mutex> lk(mutex_);
  pending_ids_.erase(s->id());
  if (reserved_ > 0) --reserved_;
  if (!s->creator().empty()) unreserve(s->creator());
  sessions_[s->id()] = std::move(s);
}

std::shared_ptr<HostedSession> Registry::find(const std::string& id) const {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = sessions_.find(id);
  return it == sessions_.end() ? nullptr : it->second;
}

std::shared_ptr<HostedSession> Registry::retire(const std::string& id, TimePoint now) {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return nullptr;
  std::shared_ptr<HostedSession> s = std::move(it->second);
  sessions_.erase(it);
  ended_.push_back(Ended{s, now});
  return s;
}

std::vector<std::shared_ptr<HostedSession>> Registry::reclaim(TimePoint now, double timeout, double linger) {
  std::vector<std::shared_ptr<HostedSession>> idle;
  std::lock_guard<std::mutex> lk(mutex_);
  std::erase_if(ended_, [&](const Ended& e) { return seconds(now - e.since) > linger; });
  for (auto it = sessions_.begin(); timeout > 0 && it != sessions_.end();) {
    if (it->second->idleSeconds(now) > timeout) {
      idle.push_back(it->second);
      ended_.push_back(Ended{it->second, now});
      it = sessions_.erase(it);
    } else {
      ++it;
    }
  }
  return idle;
}

Registry::Listing Registry::list(TimePoint now) const {
  Listing out;
  std::lock_guard<std::mutex> lk(mutex_);
  out.live.reserve(sessions_.size());
  for (const auto& [id, s] : sessions_) out.live.push_back(s->info(now));
  for (const Ended& e : ended_) out.ended.push_back(e.session->info(now));
  return out;
}

std::vector<std::string> Registry::ids() const {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<std::string> out;
  for (const auto& [id, s] : sessions_) out.push_back(id);
  return out;
}

int Registry::size() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return static_cast<int>(sessions_.size());
}

bool Registry::close() {
  std::lock_guard<std::mutex> lk(mutex_);
  const bool was = closed_;
  closed_ = true;
  return !was;
}

std::vector<std::shared_ptr<HostedSession>> Registry::takeAll() {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<std::shared_ptr<HostedSession>> all;
  for (auto& [id, s] : sessions_) all.push_back(std::move(s));
  sessions_.clear();
  ended_.clear();
  return all;
}

}  // namespace groundsim::session
