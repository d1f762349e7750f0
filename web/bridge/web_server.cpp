#include "bridge/web_server.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>

#include "bridge/gzip.hpp"
#include "bridge/http_read.hpp"
#include "bridge/listen.hpp"
#include "lcm/latency_trace.hpp"
#include "protocol/metrics_text.hpp"

namespace groundsim::web {

namespace {

// ordered messages a browser may fall behind by before it is dropped
constexpr std::size_t kMaxQueued = 1024;
// The kernel's send buffer of a WebSocket. Autotuned it grows to megabytes
// (net.ipv4.tcp_wmem), seconds of states that a browser which stopped
// reading would get, stale, before the newest-only slot came into play;
// bounded, a stalled browser holds at most this much (and its own receive
// buffer) in the kernel: a browser that reads, but slower than states come,
// runs that far behind. 32 KiB (Linux books twice that) still carries 60
// states/s of 32 cars (1.2 MB/s) to a browser 20 ms away.
constexpr int kSendBufferBytes = 32 * 1024;
// recording answers larger than this go in gzip to browsers that take it
constexpr std::size_t kGzipFromBytes = 8 * 1024;
// frames larger than this close the connection (Beast refuses them while
// reading); smaller ones above kMaxMessageBytes are answered with an error
constexpr std::size_t kMaxFrameBytes = 64 * 1024;

const char* contentType(const std::string& name) {
  auto ends = [&](const char* ext) {
    const std::string e(ext);
    return name.size() >= e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".map") || ends(".json")) return "application/json";
  if (ends(".png")) return "image/png";
  if (ends(".wasm")) return "application/wasm";  // the page's predictor (web/wasm)
  return "application/octet-stream";
}

class WsSession : public Peer, public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, Hub& hub, std::shared_ptr<WebTraffic> traffic)
      : ws_(std::move(socket)),
        hub_(hub),
        traffic_(std::move(traffic)),
        // a burst of a second's worth (a page catching up after a stall), then the rate
        messages_(hub.limits().messages_per_second, std::max(1.0, hub.limits().messages_per_second)),
        pause_(ws_.get_executor()) {
    beast::error_code ec;
    const auto ep = ws_.next_layer().socket().remote_endpoint(ec);
    name_ = ec ? "?" : ep.address().to_string() + ":" + std::to_string(ep.port());
  }

  void start(http::request<http::string_body> req) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxFrameBytes);
    ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->open_ = true;
      self->hub_.attach(self.get());
      self->read();
    });
  }

  void send(std::shared_ptr<const std::string> msg) override {
    if (!open_ || closing_) return;
    if (queue_.size() >= kMaxQueued) {
      std::fprintf(stderr, "groundsim-web: browser %s stopped reading (%zu messages queued): closing\n",
                   name_.c_str(), queue_.size());
      // not from inside the hub's loop over its peers: later, on its own
      closing_ = true;
      asio::post(ws_.get_executor(), [self = shared_from_this()] { self->close(); });
      return;
    }
    queue_.push_back(std::move(msg));
    write();
  }
  void sendLatest(Slot slot, std::shared_ptr<const std::string> msg) override {
    if (!open_) return;
    auto& s = latest_[static_cast<int>(slot)];
    if (s && slot == Slot::State) {
      ++states_skipped_;
      ++traffic_->states_skipped;
    }
    s = std::move(msg);
    write();
  }
  std::string describe() const override { return name_; }
  PeerStats stats() const override {
    PeerStats st;
    st.states_sent = states_sent_;
    st.states_skipped = states_skipped_;
    st.queued = queue_.size();
    for (const auto& m : queue_) st.waiting_bytes += m->size();
    for (const auto& m : latest_)
      if (m) st.waiting_bytes += m->size();
    beast::error_code ec;
    asio::socket_base::send_buffer_size size;
    ws_.next_layer().socket().get_option(size, ec);
    st.send_buffer = ec ? -1 : size.value();
    return st;
  }

 private:
  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      const std::string text = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      if (self->ws_.got_text()) self->hub_.onText(self.get(), text); else self->hub_.onBinary(self.get());
      if (self->open_) self->readNext();
    });
  }

  // A browser sending faster than --browser-messages waits: its next
  // message is read once the rate allows (TCP holds the rest, and the page's
  // own sends back up), so one page's flood costs the bridge a bounded share
  // of its thread, and nothing it sent is dropped.
  void readNext() {
    const double wait = messages_.take(TokenBucket::Clock::now());
    if (wait <= 0) return read();
    pause_.expires_after(std::chrono::microseconds(static_cast<std::int64_t>(wait * 1e6) + 1));
    // then takes its token (a read here, without one, let twice the rate in)
    pause_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (!ec && self->open_) self->readNext();
    });
  }

  void write() {
    if (writing_ || !open_) return;
    if (!queue_.empty()) {
      current_ = std::move(queue_.front());
      queue_.pop_front();
    } else {
      auto it = std::find_if(std::begin(latest_), std::end(latest_), [](const auto& m) { return m != nullptr; });
      if (it == std::end(latest_)) return;
      if (it == std::begin(latest_) + static_cast<int>(Slot::State)) {
        ++states_sent_;
        ++traffic_->states_forwarded;
      }
      current_ = std::move(*it);
    }
    writing_ = true;
    if (net::LatencyTrace::on()) traceSend(*current_);
    ws_.text(true);
    ws_.async_write(asio::buffer(*current_), [self = shared_from_this()](beast::error_code ec, std::size_t n) {
      self->writing_ = false;
      self->current_.reset();
      self->traffic_->bytes_sent += n;
      if (ec) return self->close();
      self->write();
    });
  }

  // The latency trace: which state this browser is sent, and when.
  void traceSend(const std::string& msg) const {
    static const std::string state = "{\"op\":\"state\"", seq = "\"seq\":";
    if (msg.compare(0, state.size(), state) != 0) return;
    const auto at = msg.find(seq);
    if (at == std::string::npos) return;
    net::LatencyTrace::line("wsend %s %lld %lld", name_.c_str(), std::atoll(msg.c_str() + at + seq.size()),
                            static_cast<long long>(net::LatencyTrace::nowUs()));
  }

  // Detaches from the hub once; the socket goes when the last handler
  // holding this session returns.
  void close() {
    if (!open_) return;
    open_ = false;
    hub_.detach(this);
    pause_.cancel();
    queue_.clear();
    for (auto& m : latest_) m.reset();
    beast::error_code ec;
    ws_.next_layer().socket().shutdown(tcp::socket::shutdown_both, ec);
    ws_.next_layer().socket().close(ec);
  }

  websocket::stream<beast::tcp_stream> ws_;
  Hub& hub_;
  std::shared_ptr<WebTraffic> traffic_;
  std::string name_;
  beast::flat_buffer buffer_;
  std::deque<std::shared_ptr<const std::string>> queue_;
  std::shared_ptr<const std::string> latest_[kSlots];
  std::shared_ptr<const std::string> current_;
  bool writing_ = false, open_ = false, closing_ = false;
  std::uint64_t states_sent_ = 0, states_skipped_ = 0;
  TokenBucket messages_;       // messages read a second (--browser-messages)
  asio::steady_timer pause_;   // waiting for the next read's turn
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Hub& hub, std::shared_ptr<const std::map<std::string, StaticFile>> files,
              std::shared_ptr<WebTraffic> traffic, std::shared_ptr<const Recordings> recordings,
              std::shared_ptr<std::function<std::string()>> more_metrics)
      : reader_(std::move(socket)),
        hub_(hub),
        files_(std::move(files)),
        traffic_(std::move(traffic)),
        recordings_(std::move(recordings)),
        more_metrics_(std::move(more_metrics)) {}

  // the page's requests are GETs and small POSTs; 30 s to send one
  void read() {
    reader_.read({.header_bytes = 8192, .body_bytes = 4096, .timeout = std::chrono::seconds(30)},
                 [self = shared_from_this()](http::request<http::string_body> req) { self->handle(std::move(req)); });
  }

 private:
  void handle(http::request<http::string_body> req) {
    std::string target(req.target());
    const auto q = target.find('?');
    const std::string path = target.substr(0, q);
    if (path == "/ws" && websocket::is_upgrade(req)) {
      reader_.stream().expires_never();
      // the small send buffer is for the state stream only: an HTTP answer
      // (a recording's window of 1.6 MB) would leave 64 KiB per ACK round
      tcp::socket socket = reader_.stream().release_socket();
      beast::error_code ec;
      socket.set_option(asio::socket_base::send_buffer_size(kSendBufferBytes), ec);
      std::make_shared<WsSession>(std::move(socket), hub_, traffic_)->start(std::move(req));
      return;
    }
    auto res = std::make_shared<http::response<http::string_body>>();
    res->version(req.version());
    res->keep_alive(req.keep_alive());
    res->set(http::field::server, "groundsim-web");
    auto it = files_->find(path);
    if (req.method() != http::verb::get && req.method() != http::verb::head) {
      res->result(http::status::method_not_allowed);
      res->set(http::field::content_type, "text/plain");
      res->set(http::field::allow, "GET, HEAD");
      res->body() = "only GET\n";
    } else if (path == "/metrics" || path == "/health") {
      // from counters on this thread: nothing to wait for
      const bool metrics = path == "/metrics";
      res->result(http::status::ok);
      res->set(http::field::content_type, metrics ? net::kMetricsContentType : "application/json");
      res->set(http::field::cache_control, "no-store");
      if (req.method() == http::verb::get)
        res->body() = metrics ? bridgeMetrics(hub_, *traffic_) + (*more_metrics_ ? (*more_metrics_)() : "")
                              : bridgeHealth(hub_) + "\n";
    } else if (path == "/recordings" || path.rfind("/recordings/", 0) == 0) {
      return serveRecording(path, q == std::string::npos ? "" : target.substr(q + 1),
                            acceptsGzip(std::string(req[http::field::accept_encoding])), std::move(res));
    } else if (it == files_->end()) {
      res->result(http::status::not_found);
      res->set(http::field::content_type, "text/plain");
      res->body() = "not found: " + path + "\n";
    } else {
      res->result(http::status::ok);
      res->set(http::field::content_type, it->second.content_type);
      res->set(http::field::cache_control, "no-cache");
      if (req.method() == http::verb::get) res->body() = it->second.body;
    }
    write(std::move(res));
  }

  // Reading a recording may take a while (a window of a large file): on a
  // thread of its own, at most kRecordingReaders at once (503 beyond), the
  // answer posted back to this socket's I/O thread.
  static constexpr int kRecordingReaders = 4;  // a replay's seek, its window, the next one, a listing
  void serveRecording(std::string path, std::string query, bool gzip_ok,
                      std::shared_ptr<http::response<http::string_body>> res) {
    static std::atomic<int> readers{0};
    if (readers.fetch_add(1) >= kRecordingReaders) {
      readers.fetch_sub(1);
      res->result(http::status::service_unavailable);
      res->set(http::field::content_type, "application/json");
      res->set(http::field::retry_after, "1");
      res->body() = "{\"error\":\"4 recordings are being read: try again\"}\n";
      return write(std::move(res));
    }
    std::thread([self = shared_from_this(), path = std::move(path), query = std::move(query), gzip_ok, res]() mutable {
      HttpAnswer a = self->recordings_->answer(path, query);
      // large answers (windows of states) in gzip where the browser takes it
      bool zipped = false;
      if (gzip_ok && a.body.size() > kGzipFromBytes)
        if (auto z = gzip(a.body)) {
          a.body = std::move(*z);
          zipped = true;
        }
      readers.fetch_sub(1);
      asio::post(self->reader_.stream().get_executor(), [self, res, a, zipped] {
        res->result(static_cast<http::status>(a.status));
        res->set(http::field::content_type, a.content_type);
        res->set(http::field::vary, "Accept-Encoding");
        if (zipped) res->set(http::field::content_encoding, "gzip");
        res->set(http::field::cache_control, "no-store");
        res->body() = a.body;
        self->write(res);
      });
    }).detach();
  }

  void write(std::shared_ptr<http::response<http::string_body>> res) {
    res->prepare_payload();
    http::async_write(reader_.stream(), *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t n) {
      self->traffic_->bytes_sent += n;
      if (ec || !res->keep_alive()) {
        beast::error_code e;
        self->reader_.stream().socket().shutdown(tcp::socket::shutdown_send, e);
        return;
      }
      self->read();
    });
  }

  RequestReader reader_;
  Hub& hub_;
  std::shared_ptr<const std::map<std::string, StaticFile>> files_;
  std::shared_ptr<WebTraffic> traffic_;
  std::shared_ptr<const Recordings> recordings_;
  std::shared_ptr<std::function<std::string()>> more_metrics_;
};

}  // namespace

std::string bridgeMetrics(const Hub& hub, const WebTraffic& traffic) {
  net::MetricsText m;
  net::writeBuildInfo(m, "groundsim-web");
  m.single("groundsim_web_browsers", "gauge", "Browsers connected over WebSocket.",
           static_cast<std::uint64_t>(hub.browsers()));
  m.single("groundsim_web_sessions_watched", "gauge", "Sessions at least one browser watches or drives.",
           static_cast<std::uint64_t>(hub.sessionsWatched()));
  m.single("groundsim_web_states_forwarded_total", "counter", "State messages written to browsers.",
           traffic.states_forwarded);
  m.single("groundsim_web_states_skipped_total", "counter",
           "States a slow browser never got: replaced in its newest-only slot by a newer one before being written.",
           traffic.states_skipped);
  m.single("groundsim_web_lcm_messages_dropped_total", "counter",
           "Messages from the server's bus dropped as undecodable.", hub.undecodable());
  m.single("groundsim_web_browser_messages_refused_total", "counter",
           "Browser messages refused (malformed, not allowed, or failed), each answered with an error.",
           hub.refused());
  m.single("groundsim_web_sent_bytes_total", "counter",
           "Bytes written to browsers: WebSocket message payloads and whole HTTP responses.", traffic.bytes_sent);
  return m.take();
}

std::string bridgeHealth(const Hub& hub) {
  return "{\"status\":\"ok\",\"browsers\":" + std::to_string(hub.browsers()) +
         ",\"sessions_watched\":" + std::to_string(hub.sessionsWatched()) + "}";
}

std::map<std::string, StaticFile> loadStaticFiles(const std::string& dir) {
  std::map<std::string, StaticFile> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    std::ifstream f(e.path(), std::ios::binary);
    std::stringstream body;
    body << f.rdbuf();
    const std::string name = e.path().filename().string();
    files["/" + name] = {contentType(name), body.str()};
    if (name == "index.html") files["/"] = files["/" + name];
  }
  return files;
}

WebServer::WebServer(asio::io_context& io, Hub& hub, std::map<std::string, StaticFile> files,
                     std::string recordings_dir, std::string configs_dir)
    : io_(io),
      hub_(hub),
      files_(std::make_shared<const std::map<std::string, StaticFile>>(std::move(files))),
      traffic_(std::make_shared<WebTraffic>()),
      recordings_(std::make_shared<const Recordings>(std::move(recordings_dir), std::move(configs_dir))),
      acceptor_(io) {}

void WebServer::listen(const std::string& address, unsigned short port) {
  port_ = listenOn(acceptor_, address, port);
  accept();
}

void WebServer::accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!ec) {
      socket.set_option(tcp::no_delay(true), ec);
      std::make_shared<HttpSession>(std::move(socket), hub_, files_, traffic_, recordings_, more_metrics_)->read();
    }
    if (acceptor_.is_open()) accept();
  });
}

}  // namespace groundsim::web
