#include "bridge/session_table.hpp"

#include <algorithm>

namespace groundsim::web {

SessionEntry& SessionTable::open(const std::string& id) { return entries_[id]; }

SessionEntry* SessionTable::find(const std::string& id) {
  auto it = entries_.find(id);
  return it == entries_.end() ? nullptr : &it->second;
}

const SessionEntry* SessionTable::find(const std::string& id) const {
  auto it = entries_.find(id);
  return it == entries_.end() ? nullptr : &it->second;
}

void SessionTable::prune() {
  std::erase_if(entries_, [](const auto& e) { return e.second.idle(); });
}

std::size_t SessionTable::watchedCount() const {
  return static_cast<std::size_t>(
      std::count_if(entries_.begin(), entries_.end(), [](const auto& e) { return !e.second.watchers.empty(); }));
}

int SessionTable::ownedBy(std::uint64_t creator) const {
  int n = 0;
  for (const auto& [id, s] : entries_) n += s.creator == creator && s.owned();
  return n;
}

void SessionTable::setScenario(const std::string& id, std::string doc) {
  auto [it, added] = scenarios_.insert_or_assign(id, std::move(doc));
  if (added) scenario_order_.push_back(id);
  forgetOldScenarios();
}

void SessionTable::forgetOldScenarios() {
  std::size_t detached = 0, bytes = 0;
  for (const auto& [id, doc] : scenarios_)
    if (!entries_.count(id)) ++detached, bytes += doc.size();
  // oldest first; a session with an entry keeps its document (and its place)
  for (auto it = scenario_order_.begin();
       it != scenario_order_.end() && (detached > kMaxDetached || bytes > kMaxDetachedBytes);) {
    auto doc = scenarios_.find(*it);
    if (doc == scenarios_.end()) {
      it = scenario_order_.erase(it);
    } else if (entries_.count(*it)) {
      ++it;
    } else {
      --detached;
      bytes -= doc->second.size();
      scenarios_.erase(doc);
      it = scenario_order_.erase(it);
    }
  }
}

const std::string* SessionTable::scenario(const std::string& id) const {
  auto it = scenarios_.find(id);
  return it == scenarios_.end() ? nullptr : &it->second;
}

void SessionTable::updateWatched(const std::string& id) {
  const SessionEntry* s = find(id);
  const int n = s ? static_cast<int>(s->watchers.size()) : 0;
  std::lock_guard<std::mutex> lk(shared_mu_);
  if (n) watched_[id] = n; else watched_.erase(id);
}

bool SessionTable::watched(const std::string& id) {
  std::lock_guard<std::mutex> lk(shared_mu_);
  auto it = watched_.find(id);
  return it != watched_.end() && it->second > 0;
}

bool SessionTable::noteBusState(const std::string& id, double t, std::chrono::steady_clock::time_point now) {
  std::lock_guard<std::mutex> lk(shared_mu_);
  Seen& b = seen_[id];
  b.t = t;
  b.last = now;
  auto it = watched_.find(id);
  return it != watched_.end() && it->second > 0;
}

std::vector<BusSession> SessionTable::onBus(std::chrono::steady_clock::time_point now, std::chrono::seconds within) {
  std::vector<BusSession> out;
  std::lock_guard<std::mutex> lk(shared_mu_);
  for (auto it = seen_.begin(); it != seen_.end();) {
    if (now - it->second.last > within) {
      it = seen_.erase(it);
      continue;
    }
    out.push_back({it->first, it->second.t});
    ++it;
  }
  return out;
}

}  // namespace groundsim::web
