#include "metrics.hpp"

#include <cstdio>
#include <list>
#include <optional>
#include <stdexcept>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "protocol/metrics_text.hpp"

namespace groundsim::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

namespace {
class Connection;
}

// Everything below runs on the listener's thread only: no locks.
struct MetricsListener::Impl {
  Impl(Handler h, Limits l) : handler(std::move(h)), limits(l) {}
  void accept();

  asio::io_context io{1};
  tcp::acceptor acceptor{io};
  asio::steady_timer retry{io};
  Handler handler;
  Limits limits;
  std::list<std::shared_ptr<Connection>> open;  // oldest first
  unsigned short port = 0;
  std::thread thread;
};

namespace {

// One client connection: requests read whole (bounded in size and time),
// answered, repeated while the client keeps the connection alive.
class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(tcp::socket socket, MetricsListener::Impl& owner)
      : stream_(std::move(socket)), owner_(owner), buffer_(owner.limits.request_bytes) {}

  std::list<std::shared_ptr<Connection>>::iterator where;  // in owner_.open

  void read() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(owner_.limits.request_bytes));
    parser_->body_limit(owner_.limits.request_bytes);
    // one deadline for the whole request: a client trickling bytes is closed too
    stream_.expires_after(timeout());
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t n) {
      if (ec || n > self->owner_.limits.request_bytes) return self->close();
      self->answer(self->parser_->release());
    });
  }

  // Idempotent; the last handler holding the connection frees it.
  void close() {
    if (closed_) return;
    closed_ = true;
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.socket().close(ec);
    owner_.open.erase(where);
  }

 private:
  std::chrono::steady_clock::duration timeout() const {
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(owner_.limits.timeout_s));
  }

  void answer(http::request<http::string_body> req) {
    HttpAnswer a;
    if (req.method() != http::verb::get) {
      a.status = 405;
      a.body = "only GET\n";
    } else {
      const std::string_view target(req.target().data(), req.target().size());
      const std::string_view path = target.substr(0, target.find('?'));
      try {
        a = owner_.handler(path);
      } catch (const std::exception& e) {
        a = HttpAnswer{500, "text/plain; charset=utf-8", std::string("internal error: ") + e.what() + "\n"};
      }
    }
    auto res = std::make_shared<http::response<http::string_body>>(static_cast<http::status>(a.status), req.version());
    res->set(http::field::server, "groundsim-server");
    res->set(http::field::content_type, a.content_type);
    res->set(http::field::cache_control, "no-store");
    if (a.status == 405) res->set(http::field::allow, "GET");
    res->keep_alive(req.keep_alive());
    res->body() = std::move(a.body);
    res->prepare_payload();
    stream_.expires_after(timeout());
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec || !res->keep_alive()) return self->close();
      self->read();
    });
  }

  beast::tcp_stream stream_;
  MetricsListener::Impl& owner_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  bool closed_ = false;
};

}  // namespace

void MetricsListener::Impl::accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!acceptor.is_open()) return;
    if (ec) {
      // out of file descriptors, say: try again a little later rather than spin
      retry.expires_after(std::chrono::milliseconds(100));
      retry.async_wait([this](beast::error_code e) {
        if (!e) accept();
      });
      return;
    }
    // full: the oldest goes (a scraper's request takes microseconds, so
    // the connections that linger are the ones that send nothing)
    while (!open.empty() && static_cast<int>(open.size()) >= limits.connections) {
      auto oldest = open.front();
      oldest->close();
    }
    auto c = std::make_shared<Connection>(std::move(socket), *this);
    open.push_back(c);
    c->where = std::prev(open.end());
    c->read();
    accept();
  });
}

MetricsListener::MetricsListener(const std::string& address, unsigned short port, Handler handler, Limits limits)
    : impl_(std::make_unique<Impl>(std::move(handler), limits)) {
  try {
    const tcp::endpoint ep(asio::ip::make_address(address), port);
    impl_->acceptor.open(ep.protocol());
    impl_->acceptor.set_option(asio::socket_base::reuse_address(true));
    impl_->acceptor.bind(ep);
    impl_->acceptor.listen();
    impl_->port = impl_->acceptor.local_endpoint().port();
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot listen on " + address + ":" + std::to_string(port) + ": " + e.what());
  }
  impl_->accept();
  impl_->thread = std::thread([impl = impl_.get()] {
    for (;;) {
      try {
        impl->io.run();
        return;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "groundsim-server: metrics listener: %s\n", e.what());
      }
    }
  });
}

MetricsListener::~MetricsListener() {
  asio::post(impl_->io, [impl = impl_.get()] {
    beast::error_code ec;
    impl->acceptor.close(ec);
    impl->retry.cancel();
    while (!impl->open.empty()) {
      auto c = impl->open.front();
      c->close();
    }
    impl->io.stop();  // what is still pending (aborted reads, timers) goes with the io_context
  });
  impl_->thread.join();
}

unsigned short MetricsListener::port() const { return impl_->port; }

// ---- groundsim-server's metrics ----------------------------------------------

std::string serverMetrics(const LcmServer::Counters& c, const ResendRing::Stats& resend) {
  MetricsText m;
  writeBuildInfo(m, "groundsim-server");
  // per mode, never per session: four series however many sessions run
  static constexpr const char* kModes[4] = {"realtime", "fast", "lockstep", "vectorised"};
  m.family("groundsim_sessions", "gauge",
           "Sessions hosted (running, paused, finished or diverged, not yet stopped or reclaimed), by mode, "
           "as of the last heartbeat.");
  for (int i = 0; i < 4; ++i) m.sample("groundsim_sessions", c.sessions_by_mode[i], {{"mode", kModes[i]}});
  m.single("groundsim_sessions_limit", "gauge", "Sessions hosted at most (--max-sessions).", c.max_sessions);
  m.single("groundsim_workers", "gauge", "Stepping threads of the worker pool.", c.workers);
  m.single("groundsim_worker_load_ratio", "gauge",
           "Busy fraction of the worker pool (0 to 1) over the second before the last heartbeat, as the heartbeat "
           "reports it.",
           c.load);
  m.single("groundsim_realtime_overrun_events_total", "counter",
           "Real time overrun warnings: a real time session fell more than --max-lag behind the wall clock and "
           "skipped ahead (at most one warning per session per 5 s).",
           c.overrun_events);
  m.single("groundsim_standby_sessions", "gauge",
           "Fleets: other servers' sessions this server keeps replicas of (their scenario, newest snapshot and "
           "applied entries), and could take over.",
           c.standby_sessions);
  m.single("groundsim_standby_asks_total", "counter",
           "Fleets: re-requests this server sent, as a standby, for applied-command entries of another server's "
           "session that it missed (gap repair, docs/fleet.md).",
           c.standby_asks);
  m.single("groundsim_standby_entries_repaired_total", "counter",
           "Fleets: applied-command entries the owners sent this standby again after a re-request.",
           c.standby_repaired);
  m.single("groundsim_states_published_total", "counter",
           "State messages (state_t) published; the heartbeat's frames_published.", c.states_published);
  m.single("groundsim_requests_handled_total", "counter",
           "Datagrams received on the server's input channels (requests, drive and controls commands, vectorised "
           "requests, asset parts, re-requests); the heartbeat's requests_handled.",
           c.requests_handled);
  m.single("groundsim_errors_total", "counter",
           "Warning and error events published, and messages that could not be published; the heartbeat's errors.",
           c.errors);
  m.single("groundsim_heartbeats_sent_total", "counter", "Heartbeats (server_status_t) published.", c.heartbeats);
  m.single("groundsim_resend_requests_total", "counter", "Re-requests (resend_t) of recorders answered.",
           resend.requests);
  m.family("groundsim_resend_answers_total", "counter",
           "Messages (resent_t) sent in answer to re-requests, by status: resent (a message as first published), "
           "gone (a range older than the ring holds), limited (a range over the client's rate), unknown_session, "
           "elsewhere (a range an earlier owner of the session published, before it moved here).");
  m.sample("groundsim_resend_answers_total", resend.resent, {{"status", "resent"}});
  m.sample("groundsim_resend_answers_total", resend.gone, {{"status", "gone"}});
  m.sample("groundsim_resend_answers_total", resend.limited, {{"status", "limited"}});
  m.sample("groundsim_resend_answers_total", resend.unknown, {{"status", "unknown_session"}});
  m.sample("groundsim_resend_answers_total", resend.elsewhere, {{"status", "elsewhere"}});
  m.single("groundsim_resend_held_bytes", "gauge", "Bytes of published messages the resend ring holds for re-requests.",
           static_cast<std::uint64_t>(resend.bytes_held));
  m.single("groundsim_resend_sessions", "gauge", "Sessions whose recent frames the resend ring holds.",
           resend.sessions);
  return m.take();
}

std::string serverHealth(const LcmServer::Counters& c, const char* status) {
  int sessions = 0;
  for (int n : c.sessions_by_mode) sessions += n;
  char b[128];
  std::snprintf(b, sizeof b, "{\"status\":\"%s\",\"sessions\":%d,\"load\":%s}", status, sessions,
                metricNumber(c.load).c_str());
  return b;
}

MetricsListener::Handler serverMetricsHandler(LcmServer& server, const std::atomic<bool>& stopping) {
  return [&server, &stopping](std::string_view path) {
    if (path == "/metrics") return HttpAnswer{200, kMetricsContentType, serverMetrics(server.counters(), server.resendStats())};
    if (path == "/health") {
      // 503 while stopping and, in a fleet, while fenced (no lease: it publishes
      // nothing) or draining: a readiness probe takes it out of service then
      const char* fleet = server.fleetTrouble();
      const char* status = stopping.load() ? "stopping" : fleet ? fleet : "ok";
      return HttpAnswer{status[0] == 'o' ? 200 : 503, "application/json", serverHealth(server.counters(), status) + "\n"};
    }
    return HttpAnswer{404, "text/plain; charset=utf-8", "not found (GET /metrics or /health)\n"};
  };
}

}  // namespace groundsim::net
