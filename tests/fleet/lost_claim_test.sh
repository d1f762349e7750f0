#!/usr/bin/env bash
# A claim whose answer is lost (docs/fleet.md, "Keys whose answer was
# lost"): servers on lab hosts 1-3 reach the 3-member etcd (hosts 5-7)
# through a relay in their own host (answer_loss_relay.py, kind claim) that
# applies the first claim of a new session's id and loses its answer, so
# the claiming server's retry on the next endpoint finds the key taken and
# it claims another id. Checked: the create from host 4 gets a session that
# is listed, a relay lost a claim's answer, and the key the lost claim left
# is released by the server it names (a server log line), so that etcd's
# owners/ ends holding the session's key alone. Without the release it
# named a server that hosted nothing, for as long as that server lived.
# Exit 77 where the lab cannot be made.
#   tests/fleet/lost_claim_test.sh FLEET_LAB_SH GROUNDSIM_SERVER GROUNDSIM SCENARIO
set -euo pipefail
lab=$1 server=$2 client=$3 scenario=$4
. "$(dirname "$0")/fleet_lab_common.sh"
fleet_lab_begin fc
fail() {
  echo "FAIL: $*" >&2
  for i in 1 2 3; do echo "--- relay $i" >&2; cat "$tmp/relay$i.log" >&2 || true; done
  fleet_dump create "$tmp/create.err" 12
  exit 1
}
declare -A pid
fleet_start_servers_via_relays claim

"$lab" exec "$name" 4 "$client" create "$scenario" --duration -1 --lcm-url "$url" --timeout 20 --token-file "$tmp/tokens.json" \
  >"$tmp/create.out" 2>"$tmp/create.err" || fail "the create failed: $(cat "$tmp/create.err")"
sid=$(grep -Eo '[0-9A-F]{8}' "$tmp/create.out" | head -n 1)
[ -n "$sid" ] || fail "no session id in the create's answer: $(cat "$tmp/create.out")"
fleet_wait_owner "$sid"
echo "session $sid on $owner"
grep -h "lost its answer" "$tmp"/relay*.log || fail "no relay lost the answer of a claim (the test did not test)"

owner_keys() {
  "$lab" exec "$name" 4 etcdctl --endpoints "$endpoints" get --prefix /groundsim/owners/ --keys-only 2>/dev/null | grep -v '^$' || true
}
keys=""
for _ in $(seq 300); do
  keys=$(owner_keys)
  [ "$keys" = "/groundsim/owners/$sid" ] && break
  sleep 0.1
done
[ "$keys" = "/groundsim/owners/$sid" ] || fail "etcd's owners/ holds '$(echo $keys)', not the session's key alone"
grep -h "which does not host the session: released" "$tmp"/s*.log ||
  fail "no server said it released the key of the lost claim"
echo "the lost claim's key was released; owners/ holds $keys"
