#!/usr/bin/env bash
# A create the fleet cannot place is refused, once, and a client that
# creates again gets its session (docs/fleet.md): servers on lab hosts 1-3,
# a 3-member etcd on hosts 5-7 cut off the switch while service_bench
# (`firststate`: it waits up to 60 s for a reply, and creates again on
# ERR_UNAVAILABLE) creates a session from host 4. No server can place it;
# once the create is older than the servers' retry window (10 s) the etcd
# hosts are plugged back, and the fleet's answerer writes the create's
# placement as "nowhere" and refuses it with ERR_UNAVAILABLE naming why.
# Checked: that refusal, one server's log of it, and the create made again
# placed and publishing. Exit 77 where the lab cannot be made or the build
# has no service_bench (-DGROUNDSIM_BUILD_BENCH=OFF).
#   tests/fleet/unplaced_create_test.sh FLEET_LAB_SH GROUNDSIM_SERVER GROUNDSIM SERVICE_BENCH SCENARIO
set -euo pipefail
lab=$1 server=$2 client=$3 bench=$4 scenario=$5
[ -x "$bench" ] || { echo "SKIP: no $bench (a build without the benchmarks)" >&2; exit 77; }
. "$(dirname "$0")/fleet_lab_common.sh"
fleet_lab_begin fu
fail() {
  echo "FAIL: $*" >&2
  cat "$tmp/bench.err" >>"$tmp/bench.out" 2>/dev/null || true
  fleet_dump service_bench "$tmp/bench.out" 20
  exit 1
}
declare -A pid
fleet_start_servers

for h in 5 6 7; do "$lab" partition "$name" "$h"; done
"$lab" exec "$name" 4 "$bench" --lcm-url "$url" firststate "$scenario" --count 1 >"$tmp/bench.out" 2>"$tmp/bench.err" &
creator=$!
# the create must outlive the servers' retry window with etcd away: a step
# of the scenario (FleetNode::kCreateRetry), not a verdict
sleep 11
for h in 5 6 7; do "$lab" heal "$name" "$h"; done
echo "etcd cut off for 11 s while a create waited; plugged back"
for _ in $(seq 900); do kill -0 $creator 2>/dev/null || break; sleep 0.1; done
kill -0 $creator 2>/dev/null && { kill $creator; fail "service_bench did not end within 90 s"; }
wait $creator || fail "service_bench failed"
cat "$tmp/bench.out"
grep -q "unavailable (the fleet could not place the create" "$tmp/bench.out" || fail "the create was not refused as unavailable"
grep -q "refused: not placed in 10 s" "$tmp"/s[123].log || fail "no server logged the refusal"
[ "$(grep -c "refused: not placed" "$tmp"/s[123].log | awk -F: '{ n += $2 } END { print n }')" = 1 ] ||
  fail "the create was refused by more than one server"
grep -q "^firststate creates: 1" "$tmp/bench.out" || fail "the create made again had no first state"
echo "refused once while etcd was away, created again after"
