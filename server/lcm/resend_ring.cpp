#include "resend_ring.hpp"

#include <algorithm>
#include <limits>

namespace groundsim::net {

void ResendRing::push(Ring& r, Held h, std::size_t max_bytes, std::size_t max_messages) {
  // keep whole frames: evict by seq, never half of one
  const std::int64_t seq = h.seq;
  r.bytes += h.bytes.size();
  r.held.push_back(std::move(h));
  while (!r.held.empty() && (r.bytes > max_bytes || r.held.size() > max_messages)) {
    const std::int64_t oldest = r.held.front().seq;
    if (oldest == seq) break;  // the newest frame alone stays, whatever its size
    while (!r.held.empty() && r.held.front().seq == oldest) {
      r.bytes -= r.held.front().bytes.size();
      r.held.pop_front();
    }
  }
}

void ResendRing::addFrame(const std::string& session, std::int64_t seq, const std::string& channel,
                          const std::uint8_t* data, std::size_t size, bool sent, Clock::time_point now) {
  auto it = sessions_.find(session);
  if (it == sessions_.end()) {
    if (static_cast<int>(sessions_.size()) >= limits_.sessions) {
      auto stale = std::min_element(sessions_.begin(), sessions_.end(), [](const auto& a, const auto& b) {
        return a.second.written < b.second.written;
      });
      if (stale != sessions_.end()) sessions_.erase(stale);
    }
    it = sessions_.emplace(session, Ring{}).first;
  }
  Ring& r = it->second;
  r.written = now;
  if (r.first < 0) r.first = seq;
  // a frame is up to three messages (state, car state, contact)
  push(r, Held{seq, channel, std::vector<std::uint8_t>(data, data + size), sent}, limits_.bytes_per_session,
       3 * static_cast<std::size_t>(limits_.frames_per_session));
}

void ResendRing::addEvent(std::int64_t seq, const std::string& channel, const std::uint8_t* data, std::size_t size) {
  push(events_, Held{seq, channel, std::vector<std::uint8_t>(data, data + size)},
       std::numeric_limits<std::size_t>::max(), static_cast<std::size_t>(limits_.events));
}

ResendRing::Bucket& ResendRing::bucket(const std::string& client, Clock::time_point now) {
  auto it = buckets_.find(client);
  if (it == buckets_.end()) {
    if (static_cast<int>(buckets_.size()) >= limits_.clients) {
      auto stale = std::min_element(buckets_.begin(), buckets_.end(),
                                    [](const auto& a, const auto& b) { return a.second.used < b.second.used; });
      if (stale != buckets_.end()) buckets_.erase(stale);
    }
    Bucket b;
    b.messages = limits_.messages_per_s * limits_.burst_s;
    b.bytes = limits_.bytes_per_s * limits_.burst_s;
    b.filled = now;
    it = buckets_.emplace(client, b).first;
  }
  Bucket& b = it->second;
  const double dt = std::max(0.0, std::chrono::duration<double>(now - b.filled).count());
  b.messages = std::min(limits_.messages_per_s * limits_.burst_s, b.messages + dt * limits_.messages_per_s);
  b.bytes = std::min(limits_.bytes_per_s * limits_.burst_s, b.bytes + dt * limits_.bytes_per_s);
  b.filled = now;
  b.used = now;
  return b;
}

std::vector<ResendRing::Message> ResendRing::collect(Ring& r, const std::string& client, std::int64_t from,
                                                     std::int64_t to, Scope scope, Clock::time_point now) {
  std::vector<Message> out;
  if (r.held.empty()) return out;
  const std::int64_t oldest = r.held.front().seq, newest = r.held.back().seq;
  if (to < 0 || to > newest) to = newest;
  if (from > to) return out;
  if (from < oldest && scope == Scope::Published) from = oldest;
  if (from < r.first) {
    Message elsewhere;
    elsewhere.status = Status::Elsewhere;
    elsewhere.seq = from;
    elsewhere.last_seq = std::min(to, r.first - 1);
    out.push_back(std::move(elsewhere));
    ++stats_.elsewhere;
    from = r.first;
    if (from > to) return out;
  }
  if (from < oldest) {
    Message gone;
    gone.status = Status::Gone;
    gone.seq = from;
    gone.last_seq = std::min(to, oldest - 1);
    out.push_back(std::move(gone));
    ++stats_.gone;
    from = oldest;
    if (from > to) return out;
  }
  Bucket& b = bucket(client, now);
  // seqs are ascending: find the first held message at or after `from`
  auto it = std::lower_bound(r.held.begin(), r.held.end(), from,
                             [](const Held& h, std::int64_t s) { return h.seq < s; });
  for (; it != r.held.end() && it->seq <= to; ++it) {
    if (scope == Scope::Published && !it->sent) continue;
    // a frame is sent whole or not at all
    if (it == r.held.begin() || std::prev(it)->seq != it->seq) {
      double need_m = 0, need_b = 0;
      for (auto f = it; f != r.held.end() && f->seq == it->seq; ++f) {
        need_m += 1;
        need_b += static_cast<double>(f->bytes.size());
      }
      if (need_m > b.messages || need_b > b.bytes) {
        Message limited;
        limited.status = Status::Limited;
        limited.seq = it->seq;
        limited.last_seq = to;
        out.push_back(std::move(limited));
        ++stats_.limited;
        return out;
      }
      b.messages -= need_m;
      b.bytes -= need_b;
    }
    Message m;
    m.seq = m.last_seq = it->seq;
    m.channel = it->channel;
    m.bytes = it->bytes;
    out.push_back(std::move(m));
    ++stats_.resent;
  }
  return out;
}

std::vector<ResendRing::Message> ResendRing::answer(const std::string& client, const std::string& session,
                                                    std::int64_t from, std::int64_t to, Scope scope,
                                                    Clock::time_point now) {
  ++stats_.requests;
  if (session.empty()) return collect(events_, client, from, to, scope, now);
  auto it = sessions_.find(session);
  if (it == sessions_.end() && scope == Scope::Published) return {};
  if (it == sessions_.end()) {
    ++stats_.unknown;
    Message m;
    m.status = Status::UnknownSession;
    m.seq = from;
    m.last_seq = to;
    return {m};
  }
  return collect(it->second, client, from, to, scope, now);
}

void ResendRing::expire(Clock::time_point now) {
  const auto linger = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limits_.linger_s));
  for (auto it = sessions_.begin(); it != sessions_.end();)
    it = now - it->second.written > linger ? sessions_.erase(it) : std::next(it);
}

ResendRing::Stats ResendRing::stats() const {
  Stats s = stats_;
  s.sessions = static_cast<int>(sessions_.size());
  s.bytes_held = events_.bytes;
  for (const auto& [id, r] : sessions_) s.bytes_held += r.bytes;
  return s;
}

}  // namespace groundsim::net
