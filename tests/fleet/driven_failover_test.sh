#!/usr/bin/env bash
# A driven session survives its host (issue 20, docs/fleet.md): as
# failover_test.sh, but the sedan is driven by a client (`groundsim drive`,
# scripted controls at 20 Hz) and recorded by `groundsim record --exact` in
# host 4. The owner's host is killed 3 s in; another server takes the
# session over at epoch 2, replaying the owner's applied controls after its
# last snapshot, and the driver goes on driving it. Checked: the recording
# re-simulates bit for bit (`groundsim replay --resimulate`: every recorded
# state, both owners', equals the re-simulation of the scenario and the
# applied-command log), the takeover replayed applied entries, and no
# controls the owner acknowledged (logged) are missing from the log.
#   tests/fleet/driven_failover_test.sh FLEET_LAB_SH GROUNDSIM_SERVER GROUNDSIM SCENARIO
set -euo pipefail
lab=$1 server=$2 client=$3 scenario=$4
. "$(dirname "$0")/fleet_lab_common.sh"
fleet_lab_begin fd
fail() {
  echo "FAIL: $*" >&2
  for i in 1 2 3; do echo "--- server s$i (last lines)" >&2; tail -n 8 "$tmp/s$i.log" >&2 || true; done
  for f in record.err drive.err replay.out; do echo "--- $f" >&2; tail -n 12 "$tmp/$f" >&2 || true; done
  exit 1
}
fleet_start_servers --snapshot-interval 1

"$lab" exec "$name" 4 "$client" record --create "$scenario" --session-duration 12 --exact --out "$tmp/rec.mcap" \
  --lcm-url "$url" --token-file "$tmp/tokens.json" --timeout 10 >"$tmp/record.out" 2>"$tmp/record.err" &
recorder=$!
for _ in $(seq 600); do [ -s "$tmp/record.out" ] && break; sleep 0.1; done
sid=$(head -n 1 "$tmp/record.out")
[ -n "$sid" ] || fail "no session was created"
printf 'throttle 0.6\nwait 1.5\nsteer 0.4\nwait 1.5\nsteer -0.3\nwait 2\nthrottle 0.2\nsteer 0.2\nwait 2\nbrake 0.5\nthrottle 0\nwait 6\nquit\n' |
  "$lab" exec "$name" 4 "$client" drive "$sid" --controls car --hold --lcm-url "$url" --token-file "$tmp/tokens.json" \
    >"$tmp/drive.out" 2>"$tmp/drive.err" &
fleet_wait_owner "$sid"
# killed between two snapshots (every 1 s of simulated time), at least
# 0.35 s after the last, so that the takeover has the driver's entries to
# replay: a kill a few ticks after a snapshot left none, and the test read
# that as a replay that did not happen (the listing's T may lag by a
# heartbeat, 0.25 s, which only moves the kill later)
# (the window is looked for from 2.35 s of simulated time on, however long
# a loaded machine takes to get there; ceiling: 10 minutes of tries)
fleet_wait_session_t "$sid" 2.35
t=""; seen=""
for _ in $(seq 3000); do
  t=$(fleet_session_t "$sid") || true
  [ -n "$t" ] && python3 -c "import sys; f = float(sys.argv[1]) % 1.0; sys.exit(0 if 0.35 <= f <= 0.7 else 1)" "$t" &&
    { seen=1; break; }
  sleep 0.05
done
[ -n "$seen" ] || fail "the listing never showed the session between 0.35 and 0.7 s past a snapshot (last t '$t')"
echo "owner $owner killed at simulated time ${t:-?} s"
"$lab" kill "$name" "${owner#s}"
fleet_wait_new_owner "$sid" "$owner"
[ "$epoch" = 2 ] || fail "the new owner holds epoch $epoch, not 2"
line=$(grep -h "took over session $sid" "$tmp"/s*.log || true)
echo "$line"
entries=$(echo "$line" | sed -n 's/.*, \([0-9]*\) applied entries replayed.*/\1/p')
[ -n "$entries" ] && [ "$entries" -gt 0 ] || fail "the takeover replayed no applied entry (the driver's controls): '$line'"
for _ in $(seq 1800); do kill -0 $recorder 2>/dev/null || break; sleep 0.1; done
kill -0 $recorder 2>/dev/null && { kill $recorder; fail "the recording did not end with the session"; }
wait $recorder || fail "groundsim record exited $?"
# the recorder counts what the new owner published again (its ledger's
# state_resimulated_count), neither as loss nor written twice
grep -h "states re-simulated after a move" "$tmp/record.err" | sed 's/.*; \([0-9]* states re-simulated[^;]*\).*/record: \1/' || true
"$client" inspect "$tmp/rec.mcap" | grep "^ledger/$sid" | grep -o "state_resimulated_count [0-9]*" || fail "the ledger has no re-simulated count"
"$client" replay --resimulate "$tmp/rec.mcap" >"$tmp/replay.out" 2>&1 || fail "the recording does not re-simulate bit for bit (exit $?)"
cat "$tmp/replay.out"
grep -q "^identical: session $sid" "$tmp/replay.out" || fail "replay did not say the session is identical"
