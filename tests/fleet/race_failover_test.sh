#!/usr/bin/env bash
# A race survives its host (docs/fleet.md): the lab of failover_test.sh, a
# real-time session of two scripted sedans on a 3-gate stage
# (tests/fleet/data/two_car_stage.json). Once both cars passed gate 1 on the
# owner (its log's race events), the owner's host is killed mid-lap. Checked:
# another server takes the session over and times both players' laps and
# finishes, each lap from the start crossing the lost owner timed (the
# race's progress rides in the snapshots: without it the new owner's race
# starts afresh, no car has started, and it times no lap).
#   tests/fleet/race_failover_test.sh FLEET_LAB_SH GROUNDSIM_SERVER GROUNDSIM SCENARIO
set -euo pipefail
lab=$1 server=$2 client=$3 scenario=$4
. "$(dirname "$0")/fleet_lab_common.sh"
fleet_lab_begin fr
fail() {
  echo "FAIL: $*" >&2
  for i in 1 2 3; do echo "--- server s$i (last lines)" >&2; tail -n 12 "$tmp/s$i.log" >&2 || true; done
  exit 1
}
declare -A pid
fleet_start_servers --snapshot-interval 0.5

sid=$("$lab" exec "$name" 4 "$client" create "$scenario" --lcm-url "$url" --token-file "$tmp/tokens.json" --timeout 10 | tail -n 1)
[ -n "$sid" ] || fail "no session was created"
fleet_wait_owner "$sid"
# race events (JSON after "race: ") of TYPE in a server's log
events() { grep -h "$sid: race: " "$1" | sed 's/.*race: //' | grep "\"type\":\"$2\"" || true; }
olog="$tmp/$owner.log"
for _ in $(seq 1800); do [ "$(events "$olog" gate | wc -l)" -ge 2 ] && break; sleep 0.1; done
[ "$(events "$olog" gate | wc -l)" -ge 2 ] || fail "the cars did not pass gate 1 on $owner"
[ "$(events "$olog" finish | wc -l)" -eq 0 ] || fail "a car finished before the kill: not mid-lap"
events "$olog" start > "$tmp/starts.json"
echo "both cars past gate 1 on $owner: killing its host mid-lap"
"$lab" kill "$name" "${owner#s}"
fleet_wait_new_owner "$sid" "$owner"
grep -h "took over session $sid" "$tmp"/s*.log || true
nlog="$tmp/$new.log"
for _ in $(seq 1800); do [ "$(events "$nlog" finish | wc -l)" -ge 2 ] && break; sleep 0.1; done
events "$nlog" lap > "$tmp/laps.json"
events "$nlog" finish > "$tmp/finishes.json"
python3 - "$tmp/starts.json" "$tmp/laps.json" "$tmp/finishes.json" <<'PY' || fail "the new owner's laps"
import json, sys
starts = {j["car"]: j["t"] for j in map(json.loads, open(sys.argv[1]))}
laps = [json.loads(l) for l in open(sys.argv[2])]
fins = [json.loads(l) for l in open(sys.argv[3])]
print(f"lost owner's starts: {starts}; new owner's laps: {[(l['car'], l['lap_time']) for l in laps]}")
assert sorted(starts) == [0, 1], f"starts {starts}"
assert sorted(l["car"] for l in laps) == [0, 1], f"the new owner timed laps of {[l['car'] for l in laps]}, not both players'"
assert sorted(f["car"] for f in fins) == [0, 1], "both players finish on the new owner"
for l in laps:
    # the lap runs from the start crossing the lost owner timed to the finish crossing timed here
    want = l["t"] - starts[l["car"]]
    assert abs(l["lap_time"] - want) < 1e-9, f"car {l['car']}: lap {l['lap_time']} s, crossings say {want} s"
    assert l["best"], f"car {l['car']}: its only lap is its best"
PY
echo "PASS: the race went on on $new with both players' laps"
