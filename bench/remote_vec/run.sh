#!/bin/sh
# Per-step overhead of a vectorised session over LCM against the same batch
# in process, in a private network namespace (root: unshare -n). The server
# (one worker) runs on core 0, the client and the in-process batch on core 1.
# Usage: [SIZES=16,256,1024] [REPEATS=5] bench/remote_vec/run.sh BUILD_DIR [SCENARIO]   (docs/experiments.md)
set -eu
build=${1:?usage: run.sh BUILD_DIR [SCENARIO]}
here=$(cd "$(dirname "$0")" && pwd)
scenario=${2:-$here/../../configs/tasks/fast_car.json}
exec unshare -n sh -eu -c '
ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo
b=$1; scenario=$2
url="udpm://239.255.76.67:7667?ttl=0"
out=$(mktemp)
taskset -c 0 "$b/server/lcm/groundsim-server" --lcm-url "$url" --workers 1 --max-envs 4096 --quiet >"$out" & pid=$!
i=0; until grep -q "groundsim-server ready" "$out"; do i=$((i+1)); [ $i -lt 200 ] || exit 1; sleep 0.05; done
taskset -c 0 "$b/bench/remote_vec/remote_vec_bench" "$scenario" --lcm-url "$url" --sizes ${SIZES:-16,256,1024} --repeats ${REPEATS:-5}
kill -TERM $pid; wait $pid
' sh "$build" "$scenario"
