#!/bin/sh
# Runs a command in a fresh network namespace with multicast on loopback, so
# every integration test has its own private LCM network (no cross-talk with
# other tests, other users or the host). Root uses `unshare -n`; others try a
# user namespace (`unshare -rn`). Exit 77 (CTest SKIP_RETURN_CODE) when
# neither is possible, saying why.
setup='ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo'
if [ "$(id -u)" = 0 ] && unshare -n true 2>/dev/null; then
  exec unshare -n sh -c "$setup && exec \"\$@\"" sh "$@"
fi
if unshare -rn true 2>/dev/null; then
  exec unshare -rn sh -c "$setup && exec \"\$@\"" sh "$@"
fi
echo "SKIP: cannot create a network namespace (need root for unshare -n, or unprivileged user namespaces for unshare -rn)" >&2
exit 77
