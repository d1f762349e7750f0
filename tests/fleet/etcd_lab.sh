#!/bin/sh
# Runs a fleet test in a fresh network namespace with only loopback up, so
# the etcd it starts (tests/fleet/etcd_process.cpp: 127.0.0.1, its own
# ports, a temporary data directory) is private to the test: tests run in
# parallel without seeing each other, and no traffic leaves the namespace.
# Root uses `unshare -n`; others try a user namespace (`unshare -rn`).
# Exit 77 (CTest SKIP_RETURN_CODE), saying why, without etcd or namespaces.
#   tests/fleet/etcd_lab.sh COMMAND...     (GROUNDSIM_ETCD: the etcd binary, default: etcd on PATH)
etcd=${GROUNDSIM_ETCD:-$(command -v etcd || true)}
if [ -z "$etcd" ] || [ ! -x "$etcd" ]; then
  echo "SKIP: no etcd (apt-get install etcd-server, or set GROUNDSIM_ETCD)" >&2
  exit 77
fi
export GROUNDSIM_ETCD="$etcd"
setup='ip link set lo up'
if [ "$(id -u)" = 0 ] && unshare -n true 2>/dev/null; then
  exec unshare -n sh -c "$setup && exec \"\$@\"" sh "$@"
fi
if unshare -rn true 2>/dev/null; then
  exec unshare -rn sh -c "$setup && exec \"\$@\"" sh "$@"
fi
echo "SKIP: cannot create a network namespace (need root for unshare -n, or unprivileged user namespaces for unshare -rn)" >&2
exit 77
