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
server() { taskset -c 0 "$b/server/lcm/groundsim-server" --lcm-url "$url" --workers 1 --max-sessions 1000 --quiet "$@" & pid=$!; sleep 0.5; }
echo "== lockstep round trip (server on core 0, 1 worker)"
server
taskset -c 1 "$b/bench/service/service_bench" --lcm-url "$url" roundtrip "$here/light.json" --n 10000
kill -TERM $pid; wait $pid
for n in ${SESSIONS:-100 200 300}; do
  echo "== $n real time sessions at 50 Hz, 3 subscribers (server on core 0, 1 worker)"
  server
  taskset -c 1 "$b/bench/service/service_bench" --lcm-url "$url" sessions "$here/light.json" --count $n --seconds 10
  kill -TERM $pid; wait $pid
done
' sh "$build" "$here"
