// Client ids (request_t.client_id, vec_request_t.client_id): "PRINCIPAL/INSTANCE".
// The principal is who is asking, the same for every process of one user
// on one host ("cli-alice@lab3"), or what GROUNDSIM_CLIENT names; the
// instance (pid and a random number) routes replies to one process. A
// server counts its per-client bounds (--client-sessions, --client-creates)
// by principal, so a shell loop of `groundsim create` is one client. LCM
// has no authentication: ids can be forged on the bus (docs/reliability.md,
// Fairness, says what that leaves protected).
#pragma once

#include <string>

namespace groundsim::net {

// "<kind>-<principal>/<pid>-<random>", kind "cli", "vec", ...; principal
// from $GROUNDSIM_CLIENT (printable, at most 48 bytes, '/' replaced), else
// "<user>@<host>".
std::string newClientId(const std::string& kind);
// What a server counts a client's sessions and creates under: the id up to
// its first '/' (a whole id without one); "(no client id)" for "".
std::string clientPrincipal(const std::string& client_id);

}  // namespace groundsim::net
