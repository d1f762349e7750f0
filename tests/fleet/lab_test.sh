#!/usr/bin/env bash
# scripts/fleet_lab.sh itself: hosts reach each other over the bridge and
# nothing else; partition and heal, total frame loss and none, a host's
# death and the teardown do what they say. Exit 77 where the lab cannot be
# made (not root, no namespaces) or without python3 (the probes' TCP).
#   tests/fleet/lab_test.sh FLEET_LAB_SH
set -euo pipefail
lab=$1
"$lab" check || exit $?
command -v python3 >/dev/null || { echo "SKIP: no python3" >&2; exit 77; }
command -v nft >/dev/null || { echo "SKIP: no nft (apt-get install nftables)" >&2; exit 77; }
name="fl$$"
trap '"$lab" down "$name" || true' EXIT
trap 'exit 130' INT TERM
"$lab" up "$name" 3

fail() { echo "lab_test: FAIL: $*" >&2; exit 1; }
# a TCP server in host 3 answering "ok"
"$lab" exec "$name" 3 python3 -c '
import socket
s = socket.socket(); s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
s.bind(("192.0.2.3", 7000)); s.listen(16)
while True:
    c, _ = s.accept(); c.sendall(b"ok"); c.close()' &
# can host I reach host 3? (1 s)
reach() {
  "$lab" exec "$name" "$1" python3 -c '
import socket, sys
try:
    c = socket.create_connection(("192.0.2.3", 7000), timeout=1.0); sys.exit(0 if c.recv(2) == b"ok" else 1)
except OSError:
    sys.exit(1)'
}
ok=0
for _ in $(seq 50); do reach 1 && { ok=1; break; }; sleep 0.1; done
[ $ok = 1 ] || fail "host 1 cannot reach host 3"
reach 2 || fail "host 2 cannot reach host 3"
[ "$("$lab" addr 2)" = 192.0.2.2 ] || fail "addr"
[ "$("$lab" hosts "$name" | wc -l)" = 3 ] || fail "hosts"
# a host has loopback and the lab's subnet only: no default route
"$lab" exec "$name" 1 ip route show default | grep -q . && fail "host 1 has a default route"
"$lab" exec "$name" 1 ip route show 224.0.0.0/4 | grep -q eth0 || fail "no multicast route"

"$lab" partition "$name" 1
reach 1 && fail "host 1 reached host 3 while partitioned"
reach 2 || fail "host 2 lost host 3 when host 1 was partitioned"
"$lab" heal "$name" 1
ok=0
for _ in $(seq 30); do reach 1 && { ok=1; break; }; sleep 0.1; done
[ $ok = 1 ] || fail "host 1 not back after heal"

"$lab" loss "$name" 1 100
reach 1 && fail "host 1 reached host 3 with 100 % of its frames dropped"
reach 2 || fail "host 2 lost host 3 when host 1's frames were dropped"
"$lab" loss "$name" 1 0
reach 1 || fail "host 1 not back after loss 0"

"$lab" kill "$name" 3
sleep 0.2
[ -z "$(ip netns pids "gs-$name-h3")" ] || fail "processes left in host 3 after kill"
reach 1 && fail "host 3 answered after its death"

"$lab" down "$name"
[ -z "$(ip netns list | awk '{print $1}' | grep -E "^gs-$name-" || true)" ] || fail "namespaces left after down"
echo "lab_test: OK"
