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
// "<user>@<host>". The server reads the principal back as the id up to its
// first '/' (SessionService::clientKey: the session layer does not link
// this one).
std::string newClientId(const std::string& kind);

}  // namespace groundsim::net
