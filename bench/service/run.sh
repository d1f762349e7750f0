#!/bin/sh
# Measures the network service in a private network namespace (root: unshare -n).
# Usage: bench/service/run.sh BUILD_DIR   (prints the figures of docs/performance-service.md)
set -eu
build=${1:?usage: run.sh BUILD_DIR}
here=$(cd "$(dirname "$0")" && pwd)
exec unshare -n sh -eu -c '
ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo
b=$1; here=$2
url="udpm://239.255.76.67:7667?ttl=0"
# waits for the server'"'"'s ready line instead of sleeping
server() {
  out=$(mktemp); taskset -c 0 "$b/server/lcm/groundsim-server" --lcm-url "$url" --workers 1 --max-sessions 1000 --client-sessions 0 --client-creates 0 --quiet "$@" >"$out" & pid=$!
  i=0; until grep -q "groundsim-server ready" "$out"; do i=$((i+1)); [ $i -lt 200 ] || exit 1; sleep 0.05; done
}
echo "== lockstep round trip (server on core 0, 1 worker)"
server
taskset -c 1 "$b/bench/service/service_bench" --lcm-url "$url" roundtrip "$here/light.json" --n 10000
kill -TERM $pid; wait $pid
for r in 1 2 10; do
  echo "== real-time factor $r (server on core 0, 1 worker)"
  server
  taskset -c 1 "$b/bench/service/service_bench" --lcm-url "$url" ratefactor "$here/light.json" --rate $r --seconds 3
  kill -TERM $pid; wait $pid
done
echo "== fairness: one 50 Hz session beside 4 fast sessions (server on core 0, 1 worker)"
server
taskset -c 1 "$b/bench/service/service_bench" --lcm-url "$url" fairness "$here/light.json" --greedy 4 --seconds 5
kill -TERM $pid; wait $pid
for n in ${SESSIONS:-100 200 300}; do
  echo "== $n real time sessions at 50 Hz, 3 subscribers (server on core 0, 1 worker)"
  server
  taskset -c 1 "$b/bench/service/service_bench" --lcm-url "$url" sessions "$here/light.json" --count $n --seconds 10
  kill -TERM $pid; wait $pid
done
' sh "$build" "$here"
