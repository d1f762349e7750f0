#include "bridge/browsers.hpp"

#include <cstdio>

#include <nlohmann/json.hpp>

namespace groundsim::web {

void PeerState::leaveSession() {
  session.clear();
  role = Role::Spectate;
  vehicle = -1;
  throttle.reset();
  grid_busy = false;
  grid_next.reset();
}

PeerState& Browsers::attach(Peer* p) {
  PeerState& ps = peers_[p];
  ps = PeerState{};
  ps.serial = next_serial_++;
  ps.allowance = std::make_shared<BrowserAllowance>(limits_);
  return ps;
}

PeerState* Browsers::find(Peer* p) {
  auto it = peers_.find(p);
  return it == peers_.end() ? nullptr : &it->second;
}

PeerState* Browsers::find(Peer* p, std::uint64_t serial) {
  PeerState* ps = find(p);
  return ps && ps->serial == serial ? ps : nullptr;
}

std::string Browsers::nameOf(Peer* p) const {
  auto it = peers_.find(p);
  return it == peers_.end() ? std::string() : it->second.player;
}

void Browsers::send(Peer* p, const std::string& text) { p->send(std::make_shared<const std::string>(text)); }

void Browsers::refuse(Peer* p, const std::string& op, const std::string& field, const std::string& reason) {
  ++refused_;
  auto it = peers_.find(p);
  if (log_ && it != peers_.end() && it->second.logged < 20) {
    ++it->second.logged;
    std::fprintf(stderr, "groundsim-web: browser %s: refused %s%s%s: %s\n", p->describe().c_str(),
                 op.empty() ? "message" : op.c_str(), field.empty() ? "" : " at ", field.c_str(), reason.c_str());
  }
  send(p, nlohmann::json{{"op", "error"}, {"request", op}, {"field", field}, {"reason", reason}}.dump());
}

}  // namespace groundsim::web
