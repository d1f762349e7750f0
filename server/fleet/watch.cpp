#include "fleet/watch.hpp"

#include "fleet/http.hpp"

namespace groundsim::fleet {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

std::int64_t i64(const json& j, const char* name) {
  auto it = j.find(name);
  if (it == j.end() || it->is_null()) return 0;
  if (it->is_string()) return std::stoll(it->get<std::string>());
  return it->get<std::int64_t>();
}

std::string bytes(const json& j, const char* name) {
  auto it = j.find(name);
  return it == j.end() || it->is_null() ? std::string() : EtcdClient::base64Decode(it->get<std::string>());
}

}  // namespace

Watch::Watch(EtcdClient& client, std::string prefix, std::int64_t start_revision, EventFn on_event, ErrorFn on_error)
    : Watch(client, std::move(prefix), start_revision, std::move(on_event), std::move(on_error), Options{}) {}

Watch::Watch(EtcdClient& client, std::string prefix, std::int64_t start_revision, EventFn on_event, ErrorFn on_error,
             Options options)
    : client_(client),
      prefix_(std::move(prefix)),
      on_event_(std::move(on_event)),
      on_error_(std::move(on_error)),
      options_(options),
      start_revision_(start_revision) {
  thread_ = std::thread([this] { run(); });
}

Watch::~Watch() { stop(); }

void Watch::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Watch::run() {
  const auto& endpoints = client_.endpoints();
  std::size_t endpoint = 0;
  std::int64_t from = start_revision_;
  if (from <= 0) {
    // "from now on": fix the revision once, so a reopened stream misses nothing
    for (;;) {
      try {
        from = client_.revision() + 1;
        break;
      } catch (const EtcdError& e) {
        if (on_error_) on_error_(e.what());
      }
      std::unique_lock lock(mutex_);
      if (wake_.wait_for(lock, std::chrono::milliseconds(200), [&] { return stopping_; })) return;
    }
  }
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
    }
    std::string why;
    const auto last = last_revision_.load();
    if (last >= from) from = last + 1;
    const bool compacted = stream(endpoint, from, why);
    connected_ = false;
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
    }
    if (compacted) {
      // why holds the compaction revision: go on from there
      const std::int64_t compact = std::stoll(why);
      if (on_error_)
        on_error_("watch " + prefix_ + ": revision " + std::to_string(from) + " is compacted; from " +
                  std::to_string(compact) + " on (events between are lost: read again)");
      from = compact;
      continue;
    }
    if (on_error_) on_error_("watch " + prefix_ + " on " + endpoints[endpoint] + ": " + why);
    endpoint = (endpoint + 1) % endpoints.size();
    std::unique_lock lock(mutex_);
    if (wake_.wait_for(lock, std::chrono::milliseconds(100), [&] { return stopping_; })) return;
  }
}

// One stream from one endpoint. Returns true when etcd canceled the watch for
// a compaction (why = the compaction revision), false when it ended
// otherwise (why = the reason).
bool Watch::stream(std::size_t endpoint, std::int64_t from, std::string& why) {
  const std::string& url = client_.endpoints()[endpoint];
  json create{{"key", EtcdClient::base64Encode(prefix_.empty() ? std::string(1, '\0') : prefix_)},
              {"range_end", EtcdClient::base64Encode(EtcdClient::prefixEnd(prefix_))},
              {"start_revision", std::to_string(from)}};
  const std::string body = json{{"create_request", create}}.dump();
  std::string pending;
  bool compacted = false;
  auto last_bytes = Clock::now();
  EtcdClient probe({url}, client_.options());

  auto on_bytes = [&](const std::string& piece) -> bool {
    last_bytes = Clock::now();
    pending += piece;
    std::size_t nl;
    while ((nl = pending.find('\n')) != std::string::npos) {
      std::string line = pending.substr(0, nl);
      pending.erase(0, nl + 1);
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      json msg;
      try {
        msg = json::parse(line);
      } catch (const std::exception& e) {
        why = std::string("bad JSON in the stream: ") + e.what();
        return false;
      }
      if (msg.contains("error")) {
        const auto& err = msg["error"];
        why = err.is_object() ? err.value("message", std::string("error")) : err.dump();
        return false;
      }
      const json& r = msg.contains("result") ? msg["result"] : msg;
      if (r.value("created", false)) {
        connected_ = true;
        ++streams_;
      }
      if (r.value("canceled", false)) {
        if (i64(r, "compact_revision") > 0) {
          compacted = true;
          why = std::to_string(i64(r, "compact_revision"));
        } else {
          why = "canceled: " + r.value("cancel_reason", std::string("by etcd"));
        }
        return false;
      }
      if (auto ev = r.find("events"); ev != r.end()) {
        for (const auto& e : *ev) {
          Event event;
          event.type = e.value("type", std::string("PUT")) == "DELETE" ? Event::Type::Delete : Event::Type::Put;
          const json& kv = e["kv"];
          event.kv.key = bytes(kv, "key");
          event.kv.value = bytes(kv, "value");
          event.kv.create_revision = i64(kv, "create_revision");
          event.kv.mod_revision = i64(kv, "mod_revision");
          event.kv.version = i64(kv, "version");
          event.kv.lease = i64(kv, "lease");
          if (event.kv.mod_revision <= last_revision_.load()) continue;  // delivered before a reopen
          on_event_(event);
          last_revision_ = event.kv.mod_revision;
        }
      }
    }
    return true;
  };
  auto keep_going = [&]() -> bool {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) {
        why = "stopped";
        return false;
      }
    }
    if (Clock::now() - last_bytes < options_.check_period) return true;
    // a silent stream: does its member still serve? (a linearizable read
    // needs a leader, so a member cut off from the others fails it too)
    try {
      probe.revision();
      last_bytes = Clock::now();
      return true;
    } catch (const EtcdError& e) {
      why = "the member stopped answering: " + e.reason();
      return false;
    }
  };
  try {
    const unsigned status = httpPostStream(parseUrl(url), "/v3/watch", body, client_.options().attempt_timeout,
                                           std::chrono::milliseconds(100), on_bytes, keep_going);
    if (status != 200 && why.empty()) why = "HTTP " + std::to_string(status);
    if (why.empty()) why = "the stream ended";
  } catch (const HttpFailure& f) {
    why = f.what();
  } catch (const std::exception& e) {
    why = e.what();
  }
  return compacted;
}

}  // namespace groundsim::fleet
