// Channel names and LCM URLs of the groundsim protocol (docs/protocol.md).
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>

namespace groundsim::net {

inline constexpr const char* kRequestChannel = "GROUNDSIM_REQUEST";  // request_t, clients -> server
inline constexpr const char* kReplyChannel = "GROUNDSIM_REPLY";      // reply_t, server -> clients
inline constexpr const char* kDriveChannel = "GROUNDSIM_DRIVE";      // drive_t, clients -> server
inline constexpr const char* kControlsChannel = "GROUNDSIM_CONTROLS";  // controls_t (road cars), clients -> server
inline constexpr const char* kEventChannel = "GROUNDSIM_EVENT";      // event_t, server -> anyone
inline constexpr const char* kStatusChannel = "GROUNDSIM_STATUS";    // server_status_t, 1 Hz
inline constexpr const char* kStatePrefix = "GROUNDSIM_STATE_";      // + session id: state_t
inline constexpr const char* kScenarioChannel = "GROUNDSIM_SCENARIO";  // scenario_t, server -> anyone
// request_t.op that asks for a session's scenario_t (answered on
// kScenarioChannel, then with a reply_t); request_t itself is unchanged
inline constexpr int8_t kOpScenario = 9;
// vectorised sessions (experiments API): vec_request_t in, vec_reply_t parts out
inline constexpr const char* kVecRequestChannel = "GROUNDSIM_VEC_REQUEST";
inline constexpr const char* kVecReplyChannel = "GROUNDSIM_VEC_REPLY";
// files sent with a scenario (docs/protocol.md, Assets): asset_part_t in,
// asset_want_t out (what a refused create still lacks)
inline constexpr const char* kAssetChannel = "GROUNDSIM_ASSET";
inline constexpr const char* kAssetWantChannel = "GROUNDSIM_ASSET_WANT";
inline constexpr const char* kCarStatePrefix = "GROUNDSIM_CAR_STATE_";  // + session id: car_state_t (road cars)

// gap repair (docs/logging.md): resend_t in, resent_t out on
// GROUNDSIM_RESENT_<client id>
inline constexpr const char* kResendChannel = "GROUNDSIM_RESEND";
inline constexpr const char* kResentPrefix = "GROUNDSIM_RESENT_";

inline std::string stateChannel(const std::string& session_id) { return kStatePrefix + session_id; }
inline std::string carStateChannel(const std::string& session_id) { return kCarStatePrefix + session_id; }
inline constexpr const char* kContactPrefix = "GROUNDSIM_CONTACT_";  // + session id: contact_state_t (objects, hits)
inline std::string contactChannel(const std::string& session_id) { return kContactPrefix + session_id; }
// + session id: applied_t, the session's applied-command log (docs/logging.md, Re-simulation)
inline constexpr const char* kAppliedPrefix = "GROUNDSIM_APPLIED_";
inline std::string appliedChannel(const std::string& session_id) { return kAppliedPrefix + session_id; }
// replica_t of a fleet's session for its standbys (docs/fleet.md)
inline constexpr const char* kReplicaPrefix = "GROUNDSIM_REPLICA_";
inline std::string replicaChannel(const std::string& session_id) { return kReplicaPrefix + session_id; }

// LCM's own default, unless LCM_DEFAULT_URL says otherwise. ttl=0 keeps
// multicast on this host.
inline std::string defaultUrl() {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  return env && *env ? env : "udpm://239.255.76.67:7667?ttl=0";
}

// Receive buffer for subscribers that must not lose messages: LCM's default
// socket buffer overflows within a burst (physics-notes: 85% lost at 1,000
// messages); 8 MiB held 100k msg/s without loss here.
inline constexpr int kReceiveBufferBytes = 8 * 1024 * 1024;

// Adds recv_buf_size to a udpm:// URL that does not set it.
inline std::string withReceiveBuffer(std::string url, int bytes = kReceiveBufferBytes) {
  if (url.empty()) url = defaultUrl();
  if (url.rfind("udpm://", 0) != 0 || url.find("recv_buf_size=") != std::string::npos) return url;
  url += url.find('?') == std::string::npos ? '?' : '&';
  return url + "recv_buf_size=" + std::to_string(bytes);
}

// Queue length of subscriptions that must not drop (LCM's default is 30 and
// drops silently; 0 would be unbounded). The queue holds messages already
// read from the socket that the handler has not consumed: for the state
// channels (~350 bytes per one-car state) 200,000 are ~70 MB; on the
// server's request channel a queue of 200,000 creates of up to
// kMaxScenarioBytes could in principle hold far more, so the server's
// receive thread does no work beyond decoding and queueing and keeps it
// near empty.
inline constexpr int kDeepQueue = 200000;

}  // namespace groundsim::net
