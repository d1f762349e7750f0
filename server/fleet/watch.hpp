// A watch of every key starting with a prefix, from a revision on, over the
// gateway's /v3/watch (a chunked stream of JSON objects, one a line). Its
// own thread holds the stream and calls on_event for each change in revision
// order. When the stream breaks (the member died or was cut off: checked
// every check_period by a small request to the same member while the stream
// is silent) it reopens on the next endpoint from the revision after the
// last event delivered, so no event is lost or repeated. A start revision
// etcd has compacted away is reported to on_error and the watch goes on from
// the compaction revision (the caller re-reads with a range: events between
// are gone). stop() (or the destructor) ends it within about
// attempt_timeout.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "fleet/etcd_client.hpp"

namespace groundsim::fleet {

class Watch {
 public:
  struct Event {
    enum class Type { Put, Delete };
    Type type = Type::Put;
    Kv kv;  // a Delete's: key and mod_revision only
  };
  using EventFn = std::function<void(const Event&)>;
  using ErrorFn = std::function<void(const std::string&)>;
  struct Options {
    std::chrono::milliseconds check_period{1000};  // a silent stream's member is asked whether it still serves
  };

  // start_revision 0: from now on. client outlives the watch.
  Watch(EtcdClient& client, std::string prefix, std::int64_t start_revision, EventFn on_event,
        ErrorFn on_error = {});
  Watch(EtcdClient& client, std::string prefix, std::int64_t start_revision, EventFn on_event, ErrorFn on_error,
        Options options);
  ~Watch();
  Watch(const Watch&) = delete;
  Watch& operator=(const Watch&) = delete;

  void stop();
  // The revision of the last event delivered (0 before any).
  std::int64_t lastRevision() const { return last_revision_.load(); }
  // True while a stream is open and etcd confirmed the watch.
  bool connected() const { return connected_.load(); }
  // Times a stream was (re)opened and confirmed.
  int streams() const { return streams_.load(); }

 private:
  void run();
  bool stream(std::size_t endpoint, std::int64_t from, std::string& why);

  EtcdClient& client_;
  std::string prefix_;
  EventFn on_event_;
  ErrorFn on_error_;
  Options options_;
  std::int64_t start_revision_;
  std::atomic<std::int64_t> last_revision_{0};
  std::atomic<bool> connected_{false};
  std::atomic<int> streams_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace groundsim::fleet
