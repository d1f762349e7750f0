#include "bridge/foxglove_client.hpp"

#include <cstdio>
#include <limits>

#include <boost/asio/post.hpp>

#include "bridge/http_read.hpp"

namespace groundsim::web::foxglove {

namespace {

// bytes read at a time from a client
constexpr std::size_t kReadChunk = 16 << 10;
// a slow client is told of its dropped messages at most this often
constexpr auto kDropWarningEvery = std::chrono::seconds(5);

}  // namespace

std::string peerName(const tcp::socket& s) {
  beast::error_code ec;
  const auto ep = s.remote_endpoint(ec);
  return ec ? "?" : ep.address().to_string() + ":" + std::to_string(ep.port());
}

Client::Client(tcp::socket socket, std::string subprotocol, const Options& opts, Counters& counters, Owner& owner)
    : ws_(std::move(socket)), opts_(opts), counters_(counters), owner_(owner), subprotocol_(std::move(subprotocol)) {
  name_ = peerName(ws_.next_layer().socket());
}

void Client::start(http::request<http::string_body> req) {
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.set_option(websocket::stream_base::decorator([p = subprotocol_](websocket::response_type& res) {
    res.set(http::field::sec_websocket_protocol, p);
    res.set(http::field::server, "groundsim-web");
  }));
  // the limits are read()'s own (a message is read piecewise and dropped past max_message_bytes)
  ws_.read_message_max(std::numeric_limits<std::size_t>::max());
  ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return;
    self->open_ = true;
    self->owner_.attach(self.get());
    self->read();
  });
}

void Client::sendControl(std::shared_ptr<const std::string> text) {
  if (!open_) return;
  if (control_.size() >= opts_.max_control) {
    if (opts_.log)
      std::fprintf(stderr, "groundsim-web: foxglove client %s left %zu control messages unread: closing\n",
                   name_.c_str(), control_.size());
    ++counters_.clients_closed;
    // not from inside the server's loop over its clients: later, on its own
    asio::post(ws_.get_executor(), [self = shared_from_this()] { self->close(); });
    open_ = false;  // nothing more is queued; close() still detaches
    return;
  }
  control_.push_back(std::move(text));
  write();
}

void Client::sendData(std::uint32_t subscription, std::uint64_t ns, std::shared_ptr<const std::string> json) {
  if (!open_) return;
  if (data_.size() >= opts_.outbox) {
    data_.pop_front();
    ++dropped_;
    ++dropped_unreported_;
    ++counters_.messages_dropped;
  }
  data_.push_back(Data{dataHeader(subscription, ns), std::move(json), subscription});
  write();
}

void Client::forget(std::uint32_t subscription) {
  std::erase_if(data_, [&](const Data& d) { return d.subscription == subscription; });
}

void Client::close() {
  const bool was_attached = attached_;
  attached_ = false;
  open_ = false;
  control_.clear();
  data_.clear();
  if (was_attached) owner_.detach(this);
  beast::error_code ec;
  ws_.next_layer().socket().shutdown(tcp::socket::shutdown_both, ec);
  ws_.next_layer().socket().close(ec);
}

// Piece by piece, so that a message over max_message_bytes is read and
// dropped as it comes (never held whole) and answered with a status error.
// One over max_frame_bytes closes the client: the bridge says why in a
// close frame (1009) and reads on, dropping what comes, until the client's
// close frame (or Beast's close timeout), rather than let Beast's own
// limit close the socket at once: Boost 1.74's teardown resets a
// connection whose client is still sending, and the client then sees
// 1006 instead of the reason.
void Client::read() {
  ws_.async_read_some(buffer_, kReadChunk, [self = shared_from_this()](beast::error_code ec, std::size_t n) {
    self->onRead(ec, n);
  });
}

void Client::onRead(beast::error_code ec, std::size_t n) {
  if (ec) return close();
  if (draining_) {
    buffer_.consume(buffer_.size());
    return read();
  }
  if (!open_) return;
  message_bytes_ += n;
  if (message_bytes_ > opts_.max_message_bytes) buffer_.consume(buffer_.size());
  if (message_bytes_ > opts_.max_frame_bytes) return tooBig();
  if (ws_.is_message_done()) onMessageDone();
  if (open_) read();
}

void Client::onMessageDone() {
  if (!ws_.got_text()) {
    owner_.refuse(this, "refused binary message: this server takes no client publishing "
                        "(no clientPublish capability) nor service calls");
  } else if (message_bytes_ > opts_.max_message_bytes) {
    owner_.refuse(this, "refused message of " + std::to_string(message_bytes_) + " bytes: at most " +
                            std::to_string(opts_.max_message_bytes));
  } else {
    owner_.onText(this, beast::buffers_to_string(buffer_.data()));
  }
  buffer_.consume(buffer_.size());
  message_bytes_ = 0;
}

void Client::tooBig() {
  ++counters_.clients_closed;
  ++counters_.client_errors;
  if (opts_.log)
    std::fprintf(stderr, "groundsim-web: foxglove client %s sent a message over %zu bytes: closing\n",
                 name_.c_str(), opts_.max_frame_bytes);
  // nothing more for it; the server forgets it now (not inside one of its loops: a read handler)
  open_ = false;
  draining_ = true;
  control_.clear();
  data_.clear();
  if (attached_) {
    attached_ = false;
    owner_.detach(this);
  }
  const std::string why = "message over " + std::to_string(opts_.max_frame_bytes) + " bytes";
  ws_.async_close(websocket::close_reason(websocket::close_code::too_big, why),
                  [self = shared_from_this()](beast::error_code) {});
  read();
}

// drops are told when the socket takes more again: the count then covers the whole stall
void Client::warnOfDrops() {
  const auto now = Clock::now();
  if (!dropped_unreported_ || now - last_drop_warning_ < kDropWarningEvery) return;
  last_drop_warning_ = now;
  control_.push_back(std::make_shared<const std::string>(
      status(Level::Warning, "dropped " + std::to_string(dropped_unreported_) +
                                 " messages: this client reads slower than they come (of " +
                                 std::to_string(opts_.outbox) + " waiting, the oldest go first)")));
  dropped_unreported_ = 0;
}

void Client::write() {
  if (writing_ || !open_) return;
  warnOfDrops();
  auto done = [self = shared_from_this()](beast::error_code ec, std::size_t n) {
    self->writing_ = false;
    self->text_.reset();
    self->current_.payload.reset();
    self->counters_.bytes_sent += n;
    if (ec) return self->close();
    self->write();
  };
  if (!control_.empty()) {
    text_ = std::move(control_.front());
    control_.pop_front();
    writing_ = true;
    ws_.text(true);
    ws_.async_write(asio::buffer(*text_), std::move(done));
    return;
  }
  if (data_.empty()) return;
  current_ = std::move(data_.front());
  data_.pop_front();
  writing_ = true;
  ++counters_.messages_sent;
  ws_.binary(true);
  // the header and the shared JSON as one message: the JSON is not copied per client
  const std::array<asio::const_buffer, 2> bufs{asio::buffer(current_.header), asio::buffer(*current_.payload)};
  ws_.async_write(bufs, std::move(done));
}

}  // namespace groundsim::web::foxglove
