// Every session a server hosts, of every kind, in one map with one id pool:
// admission (capacity and shutdown, counting creates still building), the
// lookup, retirement (stopped and reclaimed sessions linger in `ended` so
// the heartbeat can tell their last seq), idle reclamation and shutdown.
// Thread-safe: the receive thread looks up and retires, workers insert.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "hosted.hpp"

namespace groundsim::session {

class Registry {
 public:
  // Reserves a place for a create that is about to be built, or says why
  // not (code Shutdown or TooManySessions, and the reason). With a client
  // (a create's client_id) and client_max > 0, that client may hold at most
  // client_max sessions at once, creates still building included
  // (groundsim-server --client-sessions); a takeover passes no client.
  OwnerCheck admit(int max_sessions, const std::string* client = nullptr, int client_max = 0);
  // A reserved create that failed to build: its place (and the id it was
  // given, if any) is free again; `client` as given to admit.
  void cancel(const std::string& id = "", const std::string* client = nullptr);
  // A fresh id (not in use, not reserved) for a create being built.
  std::string newId();
  // An id from newId() that will not be used (the fleet holds it elsewhere).
  void cancelId(const std::string& id);
  // The built session takes its reserved place and its id (and its
  // creator's, when admitted with a client: s->creator() names it).
  void insert(std::shared_ptr<HostedSession> s);

  std::shared_ptr<HostedSession> find(const std::string& id) const;
  template <class T>
  std::shared_ptr<T> find(const std::string& id) const {
    return std::dynamic_pointer_cast<T>(find(id));
  }

  // Unknown from now on; listed among the ended for `linger` seconds.
  // Null when it was not (or no longer) registered.
  std::shared_ptr<HostedSession> retire(const std::string& id, TimePoint now);
  // Retires and returns the sessions idle for longer than `timeout` s
  // (none when timeout <= 0), and forgets the ended ones older than linger.
  std::vector<std::shared_ptr<HostedSession>> reclaim(TimePoint now, double timeout, double linger);

  struct Listing {
    std::vector<SessionInfo> live, ended;
  };
  Listing list(TimePoint now) const;
  int size() const;
  std::vector<std::string> ids() const;

  // Refuses every later admission; false when it was already closed.
  bool close();
  // Every session, handed back to be stopped (after close(), once the
  // workers that build creates have stopped); the ended are forgotten.
  std::vector<std::shared_ptr<HostedSession>> takeAll();

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<HostedSession>> sessions_;
  std::set<std::string> pending_ids_;  // given by newId(), not inserted yet
  struct Ended {
    std::shared_ptr<HostedSession> session;
    TimePoint since;
  };
  std::vector<Ended> ended_;
  int reserved_ = 0;  // admitted creates still building
  std::map<std::string, int> reserved_by_;  // of those, per client (admitted with one)
  int heldLocked(const std::string& client) const;
  void unreserve(const std::string& client);
  bool closed_ = false;
};

}  // namespace groundsim::session
