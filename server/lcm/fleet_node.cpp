#include "fleet_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fleet_owners.hpp"

namespace groundsim::net {
namespace {

using fleet::Compare;
using fleet::Op;
using Result = fleet::Compare::Result;

using fleet_owners::Owner;
using fleet_owners::ownerOf;
using fleet_owners::ownerValue;

void log(const std::string& line) { std::fprintf(stderr, "groundsim-server: fleet: %s\n", line.c_str()); }

}  // namespace

FleetNode::FleetNode(FleetOptions options, session::SessionService& service, session::Output& out)
    : options_(std::move(options)), service_(service), out_(out), client_(options_.endpoints) {
  const auto& cfg = service_.config();
  const fleet::Membership::Options mo{
      .id = options_.server_id,
      .address = options_.address,
      .build = options_.build,
      .ttl_s = options_.ttl_s,
      .prefix = options_.prefix,
      .resume_lease = true,
      .capacity = {{"sessions_free", cfg.max_sessions},
                   {"max_sessions", cfg.max_sessions},
                   {"workers", cfg.workers},
                   {"load", 0.0}},
  };
  fleet::Membership::Callbacks cb;
  cb.on_lost = [this](const std::string& why) {
    fenced_ = true;
    log("fenced (" + why + "): publishing nothing until the lease is back");
  };
  cb.on_registered = [this](std::int64_t lease) { onRegistered(lease); };
  membership_ = std::make_unique<fleet::Membership>(client_, mo, cb);
  thread_ = std::thread([this] { run(); });
}

FleetNode::~FleetNode() {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  membership_.reset();  // leaves: the key goes at once
}

std::string FleetNode::key(const std::string& kind, const std::string& rest) const {
  return options_.prefix + "/" + kind + "/" + rest;
}

// ---- ownership --------------------------------------------------------------

bool FleetNode::mayClaim() const { return !draining_ && !fenced_ && membership_->leaseId() != 0; }

std::int64_t FleetNode::claim(const std::string& id, const std::string& placement) {
  if (draining_) throw session::UnavailableError("server " + options_.server_id + " is draining");
  const std::int64_t lease = membership_->leaseId();
  if (lease == 0 || fenced_)
    throw session::UnavailableError("server " + options_.server_id + " cannot reach the fleet's etcd");
  const std::string value = ownerValue(options_.server_id, 1, placement);
  {
    std::lock_guard<std::mutex> lk(mutex_);
    claiming_.insert(id);  // its key may land before my_epochs_ has it: not a stray (scan)
  }
  struct Done {
    FleetNode& node;
    const std::string& id;
    ~Done() {
      std::lock_guard<std::mutex> lk(node.mutex_);
      node.claiming_.erase(id);
    }
  } done{*this, id};
  fleet::TxnResult t;
  try {
    t = client_.txn({Compare::version(key("owners", id), Result::Equal, 0), Compare::version(key("epochs", id), Result::Equal, 0)},
                    {Op::put(key("owners", id), value, lease), Op::put(key("epochs", id), "1")});
  } catch (const fleet::EtcdError& e) {
    // etcd did not answer (a stall under load): the claim may or may not
    // have landed, so it is released as if it had (the release deletes the
    // keys only where they still hold this claim's value), and the create
    // is refused as unavailable: the client creates again
    {
      std::lock_guard<std::mutex> lk(mutex_);
      my_epochs_[id] = 1;
      my_values_[id] = value;
    }
    release(id);
    throw session::UnavailableError("server " + options_.server_id + " could not claim the session in the fleet's etcd (" +
                                    e.what() + ")");
  }
  if (!t.succeeded) return 0;
  std::lock_guard<std::mutex> lk(mutex_);
  my_epochs_[id] = 1;
  my_values_[id] = value;
  owners_[id] = options_.server_id;
  realised_.insert(key("creates", placement));
  return 1;
}

void FleetNode::release(const std::string& id) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    releases_.push_back(id);
  }
  wake_.notify_all();
}

bool FleetNode::mayPublish(const std::string& session_id) const {
  if (fenced_) return false;
  std::lock_guard<std::mutex> lk(mutex_);
  return !disowned_.count(session_id);
}

bool FleetNode::holds(const std::string& session_id) const {
  std::lock_guard<std::mutex> lk(mutex_);
  return !disowned_.count(session_id);
}

bool FleetNode::isAnswerer() const {
  std::string first;
  for (const fleet::Member& m : membership_->members())
    if (first.empty() || m.id < first) first = m.id;
  return first.empty() || first == options_.server_id;
}

bool FleetNode::answers(const std::string& session_id, std::function<void()> unknown) {
  std::lock_guard<std::mutex> lk(mutex_);
  if (disowned_.count(session_id)) return false;
  if (my_epochs_.count(session_id)) return true;
  if (owners_.count(session_id) || standby_.count(session_id)) return false;  // its owner, or its next one, answers
  if (unknowns_.size() < kMaxUnknowns)
    unknowns_.push_back(Unknown{session_id, Clock::now() + 2 * options_.scan_period, std::move(unknown)});
  return false;
}

// ---- standbys -----------------------------------------------------------------

void FleetNode::onReplica(const session::Replica& r, const std::string& server_id) {
  if (server_id == options_.server_id) return;
  std::lock_guard<std::mutex> lk(mutex_);
  if (r.kind == session::Replica::Kind::Released) {
    standby_.erase(r.session_id);
    return;
  }
  auto it = standby_.find(r.session_id);
  if (it == standby_.end()) {
    // a session starts with its scenario replica; snapshots of one not known are not kept
    if (r.kind != session::Replica::Kind::Scenario || my_epochs_.count(r.session_id) ||
        standby_.size() >= options_.max_standby_sessions)
      return;
    it = standby_.emplace(r.session_id, Standby{}).first;
    it->second.log = StandbyLog(options_.max_log_entries);
  }
  Standby& s = it->second;
  if (r.epoch < s.epoch) return;  // a fenced old owner's
  if (r.epoch > s.epoch) {  // a new owner: what the old one sent is behind
    s.snapshot.reset();
    // the new owner's log goes on from where it resumed (a standby made
    // after a takeover learns it from the first snapshot too)
    if (s.epoch != 0 || r.epoch > 1) s.log.restart();
    s.epoch = r.epoch;
    s.heard_seq = s.heard_tick = -1;
  }
  s.owner = server_id;
  if (r.kind == session::Replica::Kind::Scenario) {
    s.scenario = r;
  } else {
    s.snapshot = r;
    s.log.rebase(r.applied_seq, r.frame_seq);
  }
}

void FleetNode::setAskAgain(AskAgain ask) {
  std::lock_guard<std::mutex> lk(mutex_);
  ask_again_ = std::move(ask);
}

void FleetNode::onApplied(const session::Applied& a) {
  std::lock_guard<std::mutex> lk(mutex_);
  // only for sessions whose scenario replica came (sent at creation, before
  // any entry): a datagram naming made-up sessions adds nothing
  auto it = standby_.find(a.session_id);
  if (it == standby_.end() || my_epochs_.count(a.session_id)) return;
  Standby& s = it->second;
  if (a.epoch < s.epoch) return;
  s.log.add(a);
}

void FleetNode::onState(const std::string& session_id, std::int64_t seq, std::int64_t tick, std::int64_t epoch) {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = standby_.find(session_id);
  if (it == standby_.end() || epoch != it->second.epoch || seq <= it->second.heard_seq) return;
  it->second.heard_seq = seq;
  it->second.heard_tick = tick;
}

void FleetNode::onListing(const std::string& server_id, std::vector<session::SessionInfo> sessions) {
  if (server_id == options_.server_id) return;
  const auto now = Clock::now();
  std::lock_guard<std::mutex> lk(mutex_);
  // servers silent for a while are gone; a flood of made-up ids is bounded
  std::erase_if(listings_, [&](const auto& kv) { return now - kv.second.at > std::chrono::seconds(6); });
  // last beats live longer than listings: a dead member whose listing went
  // must not look like a new one (never heard) while its lease lasts
  std::erase_if(beats_, [&](const auto& kv) { return now - kv.second > std::chrono::seconds(60); });
  if (!beats_.count(server_id) && beats_.size() >= kMaxServers) return;
  beats_[server_id] = now;
  if (!listings_.count(server_id) && listings_.size() >= kMaxServers) return;
  listings_[server_id] = Listing{std::move(sessions), now};
}

std::vector<session::SessionInfo> FleetNode::fleetSessions(std::vector<session::SessionInfo> own) const {
  const auto now = Clock::now();
  std::set<std::string> seen;
  for (const auto& s : own) seen.insert(s.session_id);
  std::lock_guard<std::mutex> lk(mutex_);
  for (const auto& [server, l] : listings_) {
    if (now - l.at > std::chrono::seconds(3)) continue;  // a server gone quiet
    for (const auto& s : l.sessions)
      if (seen.insert(s.session_id).second) own.push_back(s);
  }
  return own;
}

void FleetNode::updateCapacity(const session::ServiceStatus& st) {
  // every heartbeat (4 a second in a fleet) would be a write to etcd: only
  // a change of the counts, a load moved by 0.1, or every 5 s
  const int free = std::max(0, st.max_sessions - static_cast<int>(st.sessions.size()));
  const auto now = Clock::now();
  if (free == capacity_free_ && std::abs(st.load - capacity_load_) < 0.1 && now - capacity_at_ < std::chrono::seconds(5))
    return;
  capacity_free_ = free;
  capacity_load_ = st.load;
  capacity_at_ = now;
  membership_->update({{"sessions_free", free},
                       {"max_sessions", st.max_sessions},
                       {"workers", st.workers},
                       {"load", st.load}});
}

// ---- the node's thread ----------------------------------------------------------

void FleetNode::run() {
  auto next_scan = Clock::now();
  for (;;) {
    std::vector<Pending> creates;
    std::vector<std::string> releases;
    {
      std::unique_lock<std::mutex> lk(mutex_);
      wake_.wait_until(lk, next_scan,
                       [&] { return stopping_.load() || (!retry_ && (!creates_.empty() || !releases_.empty())); });
      retry_ = false;
      if (stopping_) return;
      creates.swap(creates_);
      releases.swap(releases_);
    }
    // what etcd could not do now is tried again at the next wake (a create
    // for as long as its client waits for a first answer, a release until done)
    std::size_t placed = 0, released = 0;
    try {
      for (; placed < creates.size(); ++placed) {
        const auto age = Clock::now() - creates[placed].at;
        if (age < kCreateRetry) place(creates[placed]);
        else if (age < kGiveUpBy) giveUp(creates[placed]);
      }
      for (; released < releases.size(); ++released) {
        const std::string& id = releases[released];
        std::int64_t epoch = 0;
        std::string value;
        {
          std::lock_guard<std::mutex> lk(mutex_);
          auto it = my_epochs_.find(id);
          if (it != my_epochs_.end()) epoch = it->second;
          my_epochs_.erase(id);
          if (auto v = my_values_.find(id); v != my_values_.end()) {
            value = v->second;
            my_values_.erase(v);
          }
        }
        session::Replica gone;
        gone.kind = session::Replica::Kind::Released;
        gone.session_id = id;
        gone.epoch = epoch;
        out_.publishReplica(gone);
        if (epoch > 0 && !value.empty())
          client_.txn({Compare::valueIs(key("owners", id), Result::Equal, value)},
                      {Op::del(key("owners", id)), Op::del(key("epochs", id))});
      }
      if (Clock::now() >= next_scan) {
        scan();
        next_scan = Clock::now() + options_.scan_period;
        // requests naming a session nobody owned: answered (unknown) by one server if still nobody does
        std::vector<Unknown> due;
        {
          std::lock_guard<std::mutex> lk(mutex_);
          const auto now = Clock::now();
          auto split = std::stable_partition(unknowns_.begin(), unknowns_.end(),
                                             [&](const Unknown& u) { return u.due > now; });
          due.assign(std::make_move_iterator(split), std::make_move_iterator(unknowns_.end()));
          unknowns_.erase(split, unknowns_.end());
          std::erase_if(due, [&](const Unknown& u) {
            return owners_.count(u.session_id) || standby_.count(u.session_id) || my_epochs_.count(u.session_id);
          });
        }
        if (!due.empty() && isAnswerer())
          for (const Unknown& u : due) u.answer();
      }
    } catch (const std::exception& e) {
      log(std::string("etcd: ") + e.what());
      next_scan = Clock::now() + options_.scan_period;
      std::lock_guard<std::mutex> lk(mutex_);
      if (placed < creates.size())
        creates_.insert(creates_.begin(), std::make_move_iterator(creates.begin() + placed),
                        std::make_move_iterator(creates.end()));
      if (released < releases.size())
        releases_.insert(releases_.begin(), releases.begin() + released, releases.end());
      retry_ = true;  // not at once: after a scan period
    }
  }
}

void FleetNode::scan() {
  // a member that joined (or came back with its id) has no replica of the
  // sessions already running: they send theirs again, so that it can be
  // their standby from their next snapshot on. A member that died and came
  // back between two views is the same id on a new lease.
  std::map<std::string, std::int64_t> members;
  bool joined = false;
  for (const fleet::Member& m : membership_->members()) {
    members[m.id] = m.lease;
    const auto seen = members_seen_.find(m.id);
    joined |= m.id != options_.server_id && !members_seen_.empty() &&
              (seen == members_seen_.end() || seen->second != m.lease);
  }
  members_seen_ = std::move(members);
  if (joined && !fenced_) service_.replicateAgain();
  std::map<std::string, std::string> owners;
  std::set<std::string> realised;
  std::vector<Stray> named_here;  // owners/ keys naming this server
  for (const fleet::Kv& kv : client_.range(options_.prefix + "/owners/")) {
    const Owner o = ownerOf(kv.value);
    const std::string sid = kv.key.substr(options_.prefix.size() + 8);
    owners[sid] = o.server;
    if (!o.placement.empty()) realised.insert(key("creates", o.placement));
    if (o.server == options_.server_id) named_here.push_back(Stray{sid, kv.value, o.epoch, kv.lease, {}});
  }
  std::vector<std::string> lost;  // sessions hosted here that another server owns now
  std::vector<std::pair<std::string, Standby>> orphans;
  struct Ask {
    std::string session_id;
    std::int64_t from_frame, to_frame;
  };
  std::vector<Ask> asks;
  AskAgain ask_again;
  const auto now = Clock::now();
  {
    std::lock_guard<std::mutex> lk(mutex_);
    ask_again = ask_again_;
    owners_ = owners;
    realised_ = std::move(realised);
    for (const auto& [sid, epoch] : my_epochs_) {
      auto it = owners.find(sid);
      if (it != owners.end() && it->second != options_.server_id) lost.push_back(sid);
    }
    std::erase_if(named_here, [&](Stray& k) {
      if (my_epochs_.count(k.session_id) || claiming_.count(k.session_id)) return true;
      if (auto st = standby_.find(k.session_id); st != standby_.end()) k.standby = st->second;
      return false;
    });
    for (auto& [sid, s] : standby_) {
      if (owners.count(sid)) {
        s.absent_since = {};
        // a gap still there a scan after it was found is a loss, not
        // entries on their way: the owner is asked for it again
        std::set<std::int64_t> now_seen;
        for (const StandbyLog::Gap& g : s.log.gaps()) {
          now_seen.insert(g.first_seq);
          if (s.gaps_seen.count(g.first_seq) && asks.size() < kMaxAsksPerScan)
            asks.push_back(Ask{sid, g.from_frame, g.to_frame});
        }
        s.gaps_seen = std::move(now_seen);
        continue;
      }
      if (s.absent_since == Clock::time_point{}) s.absent_since = now;
      if (s.scenario && s.snapshot) orphans.emplace_back(sid, s);
    }
  }
  if (ask_again && !fenced_)
    for (const Ask& a : asks) ask_again(a.session_id, a.from_frame, a.to_frame);
  if (!fenced_ && !draining_)
    for (Stray& k : named_here) settleStray(std::move(k));
  for (const std::string& sid : lost) {
    log("session " + sid + " is owned by " + owners[sid] + " now: dropped here");
    {
      std::lock_guard<std::mutex> lk(mutex_);
      disowned_.insert(sid);
      my_epochs_.erase(sid);
      my_values_.erase(sid);
    }
    service_.disown(sid);
  }
  if (orphans.empty() || fenced_ || draining_) return;
  const std::vector<std::string> order = ranked(loads());
  const auto me = std::find(order.begin(), order.end(), options_.server_id);
  if (me == order.end()) return;
  const auto rank = static_cast<int>(me - order.begin());
  for (auto& [sid, s] : orphans)
    if (now - s.absent_since >= rank * options_.rank_delay) tryTakeOver(sid, std::move(s));
}

void FleetNode::tryTakeOver(const std::string& sid, Standby s) {
  const std::int64_t lease = membership_->leaseId();
  if (lease == 0) return;
  const std::optional<fleet::Kv> e = client_.get(key("epochs", sid));
  std::int64_t epoch = 0;
  if (e) epoch = std::atoll(e->value.c_str());
  epoch = std::max(epoch, s.epoch) + 1;
  const std::string value = ownerValue(options_.server_id, epoch);
  const fleet::TxnResult t = client_.txn(
      {Compare::version(key("owners", sid), Result::Equal, 0),
       Compare::modRevision(key("epochs", sid), Result::Equal, e ? e->mod_revision : 0)},
      {Op::put(key("owners", sid), value, lease),
       Op::put(key("epochs", sid), std::to_string(epoch))});
  // another standby was first; or this txn's first attempt landed and its
  // answer was lost, so that the attempt on the next endpoint found the key
  // taken: the next scan finds the key naming this server (settleStray)
  if (!t.succeeded) return;
  resume(sid, std::move(s), epoch, value);
}

// An owners/ key naming this server for a session it neither hosts nor is
// claiming: a write whose answer never came back (etcd applied it, then
// the answer was lost on its way, and the retry on another endpoint found
// the key already there), or a session dropped here on an etcd error while
// the key stayed. A takeover that landed is completed from the standby's
// replicas; any other such key is deleted, so that the session's standbys
// take it over (nobody would host it while the key lives).
void FleetNode::settleStray(Stray k) {
  if (k.standby && k.standby->scenario && k.standby->snapshot && k.epoch > k.standby->epoch &&
      k.lease != 0 && k.lease == membership_->leaseId()) {
    log("owners/" + k.session_id + " names this server at epoch " + std::to_string(k.epoch) +
        " (a takeover whose answer was lost): resuming the session");
    resume(k.session_id, std::move(*k.standby), k.epoch, k.value);
    return;
  }
  log("owners/" + k.session_id + " names this server, which does not host the session: released");
  client_.txn({Compare::valueIs(key("owners", k.session_id), Result::Equal, k.value)},
              {Op::del(key("owners", k.session_id))});
}

void FleetNode::resume(const std::string& sid, Standby s, std::int64_t epoch, const std::string& value) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    my_epochs_[sid] = epoch;
    my_values_[sid] = value;
    standby_.erase(sid);
    disowned_.erase(sid);
  }
  // the entries after the snapshot up to the first gap: a gap left at the
  // owner's death is entries it acknowledged that cannot be replayed
  const std::vector<session::Applied> log_entries = s.log.replayable();
  const std::vector<StandbyLog::Gap> gaps = s.log.gaps();
  std::string missing;
  if (!gaps.empty())
    missing = "; applied entries " + std::to_string(gaps.front().first_seq) + ".." + std::to_string(gaps.back().last_seq) +
              " were never heard (" + std::to_string(s.log.size() - log_entries.size()) + " after them not replayed)";
  const std::string why = service_.adopt(*s.scenario, *s.snapshot, log_entries, s.heard_tick, epoch);
  if (!why.empty()) {
    log("cannot take over session " + sid + ": " + why);
    release(sid);
    return;
  }
  log("took over session " + sid + " from " + s.owner + " at epoch " + std::to_string(epoch) + ": snapshot at tick " +
      std::to_string(s.snapshot->tick) + ", " + std::to_string(log_entries.size()) + " applied entries replayed, its last state heard at tick " +
      std::to_string(s.heard_tick) + " (seq " + std::to_string(s.heard_seq) + ")" + missing);
}

void FleetNode::onRegistered(std::int64_t lease) {
  std::map<std::string, std::int64_t> mine;
  std::map<std::string, std::string> values;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    mine = my_epochs_;
    values = my_values_;
  }
  for (const auto& [sid, epoch] : mine) {
    try {
      const auto v = values.find(sid);
      const std::string value = v != values.end() ? v->second : ownerValue(options_.server_id, epoch);
      const std::optional<fleet::Kv> kv = client_.get(key("owners", sid));
      if (kv && kv->value == value) {
        if (kv->lease == lease) continue;  // the lease was resumed, keys and all
        // still ours under the old lease (etcd has not ended it yet): onto the new one
        if (client_.compareAndSwap(key("owners", sid), kv->mod_revision, value, lease)) continue;
      }
      // absent (it went with the old lease) and nobody took a later epoch: claim it again
      const fleet::TxnResult t = client_.txn(
          {Compare::version(key("owners", sid), Result::Equal, 0),
           Compare::valueIs(key("epochs", sid), Result::Equal, std::to_string(epoch))},
          {Op::put(key("owners", sid), value, lease)});
      if (t.succeeded) continue;
    } catch (const std::exception& e) {
      log(std::string("etcd: ") + e.what());
    }
    log("session " + sid + " was taken over while this server was cut off: dropped here");
    {
      std::lock_guard<std::mutex> lk(mutex_);
      disowned_.insert(sid);
      my_epochs_.erase(sid);
      my_values_.erase(sid);
    }
    service_.disown(sid);
  }
  fenced_ = false;
  log("lease " + std::to_string(lease) + " held again: publishing");
}

void FleetNode::drain(std::chrono::milliseconds timeout) {
  draining_ = true;
  membership_->setDraining(true);
  std::map<std::string, std::int64_t> mine;
  std::map<std::string, std::string> values;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    mine = my_epochs_;
    values = my_values_;
    for (const auto& [sid, e] : mine) disowned_.insert(sid);  // silent from now on
  }
  for (const auto& [sid, epoch] : mine) {
    service_.disown(sid);
    const auto v = values.find(sid);
    const std::string value = v != values.end() ? v->second : ownerValue(options_.server_id, epoch);
    try {  // the owner key goes, the epoch stays: a standby resumes the session at a higher epoch
      client_.txn({Compare::valueIs(key("owners", sid), Result::Equal, value)},
                  {Op::del(key("owners", sid))});
    } catch (const std::exception& e) {
      log(std::string("drain: etcd: ") + e.what());
    }
  }
  const auto end = Clock::now() + timeout;
  while (Clock::now() < end) {
    bool all = true;
    try {
      std::set<std::string> owned;
      for (const fleet::Kv& kv : client_.range(options_.prefix + "/owners/"))
        owned.insert(kv.key.substr(options_.prefix.size() + 8));
      for (const auto& [sid, e] : mine) all = all && owned.count(sid);
    } catch (const std::exception&) {
      all = false;
    }
    if (all) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  {
    std::lock_guard<std::mutex> lk(mutex_);
    for (const auto& [sid, e] : mine) {
      my_epochs_.erase(sid);
      my_values_.erase(sid);
    }
  }
  log("drained: " + std::to_string(mine.size()) + " session(s) handed over");
}

}  // namespace groundsim::net
