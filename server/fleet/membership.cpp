#include "fleet/membership.hpp"

#include <algorithm>

namespace groundsim::fleet {

using nlohmann::json;

namespace {

constexpr std::chrono::milliseconds kRetry{200};

bool validId(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
           c == '-';
  });
}

std::int64_t nowUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

bool sameView(const std::vector<Member>& a, const std::vector<Member>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].id != b[i].id || a[i].mod_revision != b[i].mod_revision || a[i].lease != b[i].lease) return false;
  return true;
}

}  // namespace

std::string Membership::serverKey(const std::string& prefix, const std::string& id) {
  return serversPrefix(prefix) + id;
}

Membership::Membership(EtcdClient& client, Options options, Callbacks callbacks)
    : client_(client), options_(std::move(options)), callbacks_(std::move(callbacks)) {
  if (!validId(options_.id))
    throw std::invalid_argument("fleet: server id '" + options_.id + "' must be 1-64 of [A-Za-z0-9._-]");
  if (options_.ttl_s < 1) throw std::invalid_argument("fleet: lease TTL must be at least 1 s");
  started_utime_ = nowUtime();
  capacity_ = options_.capacity;
  std::string why;
  if (!registerOnce(&why)) throw MembershipError(why);
  refreshView();
  worker_ = std::thread([this] { run(); });
  fencer_ = std::thread([this] { fence(); });
}

Membership::~Membership() { leave(); }

void Membership::stopThreads() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
  if (fencer_.joinable()) fencer_.join();
}

void Membership::leave() {
  stopThreads();
  std::int64_t lease = 0, old = 0;
  {
    std::lock_guard lock(mutex_);
    lease = lease_;
    old = old_lease_;
    lease_ = old_lease_ = 0;
    registered_ = false;
  }
  for (auto id : {lease, old}) {
    if (id == 0) continue;
    try {
      client_.leaseRevoke(id);
    } catch (const EtcdError&) {
      // etcd away: the key lapses with the lease
    }
  }
}

void Membership::abandon() {
  stopThreads();
  std::lock_guard lock(mutex_);
  lease_ = old_lease_ = 0;
  registered_ = false;
}

json Membership::value() const {
  std::lock_guard lock(mutex_);
  return {{"id", options_.id},           {"address", options_.address}, {"build", options_.build},
          {"capacity", capacity_},       {"draining", draining_},       {"started_utime", started_utime_}};
}

void Membership::update(const json& capacity) {
  {
    std::lock_guard lock(mutex_);
    capacity_ = capacity;
    dirty_ = true;
  }
  wake_.notify_all();
}

void Membership::setDraining(bool draining) {
  {
    std::lock_guard lock(mutex_);
    if (draining_ == draining) return;
    draining_ = draining;
    dirty_ = true;
  }
  wake_.notify_all();
}

std::vector<Member> Membership::members() const {
  std::lock_guard lock(mutex_);
  return members_;
}

std::optional<Member> Membership::member(const std::string& id) const {
  std::lock_guard lock(mutex_);
  for (const auto& m : members_)
    if (m.id == id) return m;
  return std::nullopt;
}

std::int64_t Membership::leaseId() const {
  std::lock_guard lock(mutex_);
  return registered_ ? lease_ : 0;
}

bool Membership::healthy() const {
  std::lock_guard lock(mutex_);
  return registered_ && Clock::now() - renewed_sent_ < std::chrono::seconds(ttl_s_.load());
}

std::string Membership::lastError() const {
  std::lock_guard lock(mutex_);
  return last_error_;
}

void Membership::setError(const std::string& e) {
  std::lock_guard lock(mutex_);
  last_error_ = e;
}

// Revokes a lost lease (so what it still holds goes now, not at its expiry),
// grants a new one and creates the key under it.
bool Membership::registerOnce(std::string* why_not) {
  const std::string key = this->key();
  std::int64_t old;
  {
    std::lock_guard lock(mutex_);
    old = old_lease_;
  }
  std::int64_t granted = 0;  // a lease of this attempt, revoked by the next one if this one fails
  try {
    if (old != 0 && options_.resume_lease) {
      const auto sent = Clock::now();
      if (client_.leaseKeepAliveOnce(old) > 0) {
        auto kv = client_.get(key);
        if (kv && kv->lease == old) {
          std::lock_guard lock(mutex_);
          lease_ = old;
          old_lease_ = 0;
          renewed_sent_ = sent;
          registered_ = true;
          dirty_ = true;  // what changed while lost
          republish_ = false;
          last_error_.clear();
        }
      }
      if (leaseId() == old) {
        wake_.notify_all();
        return true;
      }
    }
    if (old != 0) {
      client_.leaseRevoke(old);
      std::lock_guard lock(mutex_);
      old_lease_ = 0;
    }
    const auto sent = Clock::now();
    LeaseGrant grant = client_.leaseGrant(options_.ttl_s);
    granted = grant.id;
    const std::string text = value().dump();
    if (!client_.createIfAbsent(key, text, grant.id)) {
      std::string holder;
      try {
        client_.leaseRevoke(grant.id);
        if (auto kv = client_.get(key)) {
          holder = " (held by lease " + std::to_string(kv->lease);
          try {
            auto info = json::parse(kv->value);
            holder += ", address " + info.value("address", std::string("?"));
          } catch (const std::exception&) {
          }
          holder += ")";
        }
      } catch (const EtcdError&) {
      }
      *why_not = "fleet: server id '" + options_.id + "' is taken: " + key + " exists" + holder +
                 "; a second server with the same id is refused while the first's lease lives (it lapses within " +
                 std::to_string(grant.ttl_s) + " s of its last renewal)";
      setError(*why_not);
      return false;
    }
    {
      std::lock_guard lock(mutex_);
      lease_ = grant.id;
      ttl_s_ = grant.ttl_s;
      renewed_sent_ = sent;
      registered_ = true;
      dirty_ = republish_ = false;
      last_error_.clear();
    }
    wake_.notify_all();  // the fence's deadline moved
    return true;
  } catch (const EtcdError& e) {
    *why_not = e.what();
    setError(e.what());
    if (ttl_s_ == 0) throw;  // the first registration: the caller hears why (its lease lapses alone)
    if (granted != 0) {
      // the create's answer may be lost after etcd applied it: our key under
      // this lease would refuse the next attempt until it lapsed
      std::lock_guard lock(mutex_);
      if (old_lease_ == 0) old_lease_ = granted;
    }
    return false;
  }
}

void Membership::markLost(const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    if (!registered_) return;
    registered_ = false;
    old_lease_ = lease_;
    lease_ = 0;
  }
  if (callbacks_.on_lost) callbacks_.on_lost(reason);
}

bool Membership::keepAlive() {
  std::int64_t lease;
  {
    std::lock_guard lock(mutex_);
    if (!registered_) return true;
    lease = lease_;
  }
  const auto sent = Clock::now();
  try {
    const std::int64_t left = client_.leaseKeepAliveOnce(lease);
    if (left <= 0) {
      setError("lease " + std::to_string(lease) + " expired in etcd");
      markLost("lease " + std::to_string(lease) + " expired in etcd");
      return true;
    }
    std::lock_guard lock(mutex_);
    if (registered_ && lease_ == lease) {
      renewed_sent_ = sent;
      last_error_.clear();
    }
    return true;
  } catch (const EtcdError& e) {
    setError(e.what());
    return false;
  }
}

void Membership::publish() {
  std::int64_t lease;
  {
    std::lock_guard lock(mutex_);
    if (!registered_ || !dirty_) return;
    lease = lease_;
    dirty_ = false;
  }
  try {
    // bound to the lease: once it has expired the put is refused, so a lost
    // member never writes its key back
    client_.put(key(), value().dump(), lease);
  } catch (const EtcdError& e) {
    setError(e.what());
    std::lock_guard lock(mutex_);
    republish_ = true;  // again with the next renewal, not in a loop while etcd is away
  }
}

void Membership::refreshView() {
  std::vector<Member> view;
  try {
    const std::string prefix = serversPrefix(options_.prefix);
    for (auto& kv : client_.range(prefix)) {
      Member m;
      m.id = kv.key.substr(prefix.size());
      m.lease = kv.lease;
      m.mod_revision = kv.mod_revision;
      try {
        m.info = json::parse(kv.value);
      } catch (const std::exception&) {
        m.info = nullptr;
      }
      view.push_back(std::move(m));
    }
  } catch (const EtcdError& e) {
    setError(e.what());
    return;  // keep the last view
  }
  bool changed;
  {
    std::lock_guard lock(mutex_);
    changed = !sameView(members_, view);
    members_ = view;
  }
  if (changed && callbacks_.on_members) callbacks_.on_members(view);
}

void Membership::run() {
  const auto keepalive_period = std::chrono::milliseconds(ttl_s_.load() * 1000 / 3);
  auto next_keepalive = Clock::now() + keepalive_period;
  auto next_view = Clock::now() + options_.view_period;
  auto next_register = Clock::now();
  for (;;) {
    bool registered;
    {
      std::unique_lock lock(mutex_);
      auto until = std::min(registered_ ? next_keepalive : next_register, next_view);
      wake_.wait_until(lock, until, [&] { return stopping_ || (registered_ && dirty_); });
      if (stopping_) return;
      registered = registered_;
    }
    auto now = Clock::now();
    if (registered) {
      publish();
      if (now >= next_keepalive) {
        // a failed renewal is tried again sooner: the fence counts from the last success
        next_keepalive = now + (keepAlive() ? keepalive_period : std::min(keepalive_period, kRetry));
        std::lock_guard lock(mutex_);
        if (republish_) {
          republish_ = false;
          dirty_ = true;
        }
      }
    } else if (now >= next_register) {
      next_register = now + std::min(keepalive_period, kRetry);
      std::string why;
      if (registerOnce(&why)) {
        next_keepalive = Clock::now() + keepalive_period;
        std::int64_t lease = leaseId();
        if (callbacks_.on_registered) callbacks_.on_registered(lease);
        next_view = Clock::now();  // see ourselves back at once
      }
    }
    now = Clock::now();
    if (now >= next_view) {
      next_view = now + options_.view_period;
      refreshView();
    }
  }
}

// Independent of the worker (whose etcd calls may block for the client's
// timeouts): fires on_lost when the TTL has passed since the last renewal
// that succeeded was sent.
void Membership::fence() {
  std::unique_lock lock(mutex_);
  for (;;) {
    if (stopping_) return;
    if (!registered_) {
      wake_.wait(lock);
      continue;
    }
    const auto deadline = renewed_sent_ + std::chrono::seconds(ttl_s_.load());
    if (Clock::now() >= deadline) {
      lock.unlock();
      markLost("no lease renewal for " + std::to_string(ttl_s_.load()) + " s (etcd unreachable: " + lastError() + ")");
      lock.lock();
      continue;
    }
    wake_.wait_until(lock, deadline);
  }
}

}  // namespace groundsim::fleet
