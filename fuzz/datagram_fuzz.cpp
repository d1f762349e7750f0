// libFuzzer target: raw datagrams -> decoding -> the server's request and
// drive handling, in process. One LcmServer on LCM's memq:// transport (no
// network) lives for the whole run; each input is one datagram handed to
// LcmServer::handleDatagram exactly as LCM's receive thread would, then the
// answers it queued (replies, events, states) are drained.
//
// Input layout: datagram_input.hpp (the first byte chooses the channel and
// whether the target prefixes the rest with that channel's fingerprint).
// Links groundsim_lcm (and through it groundsim_session, groundsim_protocol,
// groundsim_scenario, groundsim_physics, groundsim_lcmtypes, liblcm).
#include <cstddef>
#include <cstdint>
#include <vector>

#include <groundsim/asset_part_t.hpp>
#include <groundsim/resend_t.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/request_t.hpp>

#include "datagram_input.hpp"
#include "lcm/lcm_server.hpp"
#include "protocol/channels.hpp"

namespace {

groundsim::net::LcmServer& server() {
  static groundsim::net::LcmServer* s = [] {
    groundsim::session::ServiceConfig cfg;
    cfg.workers = 1;
    cfg.max_sessions = 2;      // sessions the fuzzer manages to create keep stepping: keep them few
    cfg.idle_timeout = 0;
    return new groundsim::net::LcmServer("memq://", cfg, /*verbose=*/false);  // lives until exit
  }();
  return *s;
}

void appendFingerprint(std::vector<std::uint8_t>& buf, std::int64_t hash) {
  const auto h = static_cast<std::uint64_t>(hash);
  for (int i = 7; i >= 0; --i) buf.push_back(static_cast<std::uint8_t>(h >> (8 * i)));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 || size > (1u << 20)) return 0;
  groundsim::net::LcmServer& s = server();
  const std::uint8_t how = data[0];
  const bool drive = how & groundsim::fuzz::kDriveBit, asset = how & groundsim::fuzz::kAssetBit;
  // both bits: a recorder's re-request (resend_t)
  const bool resend = drive && asset;
  std::vector<std::uint8_t> buf;
  buf.reserve(size + 8);
  if (how & groundsim::fuzz::kBodyOnlyBit)
    appendFingerprint(buf, resend  ? groundsim::resend_t::getHash()
                           : asset ? groundsim::asset_part_t::getHash()
                           : drive ? groundsim::drive_t::getHash()
                                   : groundsim::request_t::getHash());
  buf.insert(buf.end(), data + 1, data + size);
  s.handleDatagram(resend  ? groundsim::net::kResendChannel
                   : asset ? groundsim::net::kAssetChannel
                   : drive ? groundsim::net::kDriveChannel
                           : groundsim::net::kRequestChannel,
                   buf.data(), static_cast<int>(buf.size()));
  // memq keeps every published message until handled: drain the answers
  while (s.lcm().handleTimeout(0) > 0) {
  }
  return 0;
}
