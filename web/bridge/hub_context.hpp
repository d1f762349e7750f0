// What the bridge's parts share, owned by the Hub (hub.hpp): the I/O
// context, the worker thread, the configuration, the bus, the browsers,
// the session table and the requests. A part keeps one of these and what
// is its own.
#pragma once

#include <boost/asio/io_context.hpp>

#include "bridge/browsers.hpp"
#include "bridge/requests.hpp"
#include "bridge/session_table.hpp"
#include "bridge/worker.hpp"

namespace groundsim::web {

struct Bus;
struct HubConfig;

struct HubContext {
  boost::asio::io_context& io;
  Worker& worker;
  const HubConfig& cfg;
  const Bus& bus;
  Browsers& browsers;
  SessionTable& sessions;
  Requests& requests;
};

}  // namespace groundsim::web
