#!/bin/sh
# A recorder killed with SIGKILL leaves a file that is readable up to about
# its last second and says it is incomplete (issue 23): a 60 s session
# recorded, the recorder killed 30 s in; read back by `groundsim inspect`,
# tried with @mcap/core (which refuses a file without a summary) and read by
# MCAP's own Python library as a stream (tests/recording/mcap_py_check.py
# --expect-cut: every whole record sound, the same states as our reader,
# the cut named). Without either reader installed: the other checks, then
# SKIP (77) naming it. Then the LCM log round
# trip: lcm-logger's log of the same session (then stopped) converted to
# MCAP holds every state the logger kept (what it missed listed as lost),
# and converted back, the same messages.
# "30 s in" is 30 s of the session's simulated time, however long a loaded
# machine takes (it was 30 s of wall time), and the recorder is killed
# while it has read everything the bus sent it (its socket's queue empty):
# what it wrote before its last second is then what the file must hold.
# Every wait is for a condition, with a ceiling that only ends a hung test.
#   crash_record.sh BUILD_DIR SOURCE_DIR     (inside tests/integration/netns_run.sh)
set -eu
build=$1; src=$2; gs=$build/client/groundsim
# requests wait 10 s for the reply (the CLI's 2 s is missed by a loaded server now and then)
rq() { cmd=$1; shift; "$gs" "$cmd" --timeout 10 "$@"; }
dir=$(mktemp -d)
# the background jobs (server, recorders, loggers) are ended on exit: $(jobs -p)
# in a command substitution lists none in dash, and the servers outlived the test
trap 'jobs -p > "$dir/.jobs"; kill $(cat "$dir/.jobs") 2>/dev/null || true; rm -rf "$dir"' EXIT
. "$src/tests/record/mcap_checks.sh"
"$build/server/lcm/groundsim-server" --quiet > "$dir/server.out" 2>&1 &
for _ in $(seq 600); do "$gs" list > /dev/null 2>&1 && break; sleep 0.1; done
lcm-logger --quiet -c 'GROUNDSIM_STATE_.*' "$dir/bus.lcm" > /dev/null 2>&1 &
logger=$!
"$gs" record --create "$src/configs/plain.json" --session-duration 60 --publish-rate 200 \
  --out "$dir/crash.mcap" > "$dir/rec.out" 2> "$dir/rec.err" &
rec=$!
for _ in $(seq 600); do [ -s "$dir/rec.out" ] && break; sleep 0.1; done
sid=$(tail -1 "$dir/rec.out")
[ -n "$sid" ] || { cat "$dir/rec.err"; echo "FAIL: no session"; exit 1; }
session_t() { rq list 2>/dev/null | awk -v s="$sid" '$1 == s {print $5}'; }
# the bytes waiting in the recorder's UDP sockets (/proc/net/udp's rx_queue, hex)
rec_queued() {
  q=0
  for fd in /proc/$rec/fd/*; do
    ino=$(readlink "$fd" 2>/dev/null | sed -n 's/^socket:\[\([0-9]*\)\]$/\1/p')
    [ -n "$ino" ] || continue
    r=$(awk -v i="$ino" 'NR > 1 && $10 == i {split($5, a, ":"); print a[2]}' /proc/net/udp)
    [ -n "$r" ] && q=$((q + 0x$r))
  done
  echo $q
}
# 30 s of the session's simulated time (ceiling: 20 minutes)
t_now=0
for _ in $(seq 2400); do
  t_now=$(session_t); t_now=${t_now:-0}
  awk -v t="$t_now" 'BEGIN { exit !(t >= 30) }' && break
  sleep 0.5
done
awk -v t="$t_now" 'BEGIN { exit !(t >= 30) }' || { echo "FAIL: the session never reached 30 s (at $t_now s)"; exit 1; }
# the session's simulation time when the recorder dies, read while the
# recorder has nothing queued (ceiling: 60 s of trying)
t_kill=""
for _ in $(seq 600); do
  if [ "$(rec_queued)" = 0 ]; then t_kill=$(session_t); break; fi
  sleep 0.1
done
[ -n "$t_kill" ] || { echo "FAIL: the recorder never caught up with the bus ($(rec_queued) bytes queued)"; exit 1; }
kill -9 $rec
wait $rec 2>/dev/null || true
"$gs" inspect "$dir/crash.mcap" > "$dir/inspect.txt" || { cat "$dir/inspect.txt"; echo "FAIL: inspect"; exit 1; }
cat "$dir/inspect.txt"
grep -q "^end *incomplete" "$dir/inspect.txt" || { echo "FAIL: the file does not say it is incomplete"; exit 1; }
# the state channel's log time (simulation time at real time) reaches 29 s
last=$(sed -n "s|^channel */$sid/state .* \.\. \([0-9.]*\) s.*|\1|p" "$dir/inspect.txt")
echo "readable up to $last s of simulation (killed at $t_kill s)"
awk -v t="$last" -v k="$t_kill" 'BEGIN { exit !(k > 0 && t >= k - 1.0) }' ||
  { echo "FAIL: only $last s readable of $t_kill"; exit 1; }
# @mcap/core needs a summary to index a file: an incomplete one it refuses, saying so
modules=""
for m in "$src/web/node_modules" "$build/web/node_modules"; do [ -d "$m/@mcap/core" ] && modules=$m && break; done
if [ -n "$modules" ] && command -v node > /dev/null; then
  GROUNDSIM_MCAP_NODE_MODULES=$modules node "$src/tests/recording/mcap_read.mjs" "$dir/crash.mcap" > /dev/null 2> "$dir/node.err" &&
    echo "note: @mcap/core opened the cut file" || echo "@mcap/core: $(cat "$dir/node.err")"
else
  mcap_note_skip "no node with @mcap/core (npm install in web/): npm's reader was not tried on the cut file"
fi
# MCAP's own Python library reads the cut file as a stream (its indexed
# reader needs the footer): every whole record sound (chunk CRCs, message
# indexes, every message valid against its schema), the record cut by the
# kill named; it reads the same states as our reader, as far
n_ours=$(sed -n "s|^channel */$sid/state *\([0-9]*\) messages.*|\1|p" "$dir/inspect.txt")
if mcap_py "$dir/crash.mcap" "$dir/py_crash.json" --expect-cut; then
  python3 - "$dir/py_crash.json" "$sid" "$n_ours" "$last" <<'PY' || { echo "FAIL: MCAP's Python library read the cut file otherwise"; exit 1; }
import json, sys
r, sid, n_ours, last = json.load(open(sys.argv[1])), sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
n, (t0, t1) = r["topics"].get(f"/{sid}/state", 0), r["log_times_s"].get(f"/{sid}/state", [0, 0])
print(f"mcap (Python): {r['end']}; indexed reader {r.get('indexed_reader')}; "
      f"{n} states to {t1:.2f} s, our reader {n_ours} to {last:.2f} s; scenario attached: {r['attachments']}")
ok = n == n_ours and abs(t1 - last) < 0.01 and f"scenario/{sid}.json" in r["attachments"]
ok = ok and r["end"].startswith("cut") and r.get("indexed_reader", "").startswith("refused")
sys.exit(0 if ok else 1)
PY
fi
# the LCM log of the session (stopped now: its final state ends it),
# through MCAP and back
rq stop "$sid" > /dev/null
sleep 1  # what the logger misses of the end is listed by the convert (exit 3), not a failure
kill $logger; wait $logger 2>/dev/null || true
# exit 3: lcm-logger itself missed datagrams (a loaded machine): the convert
# says so and lists them in the ledger; the round trip below still holds
rc=0; "$gs" convert "$dir/bus.lcm" "$dir/bus.mcap" 2> "$dir/convert.err" || rc=$?
[ $rc = 0 ] || [ $rc = 3 ] || { cat "$dir/convert.err"; echo "FAIL: convert to MCAP (exit $rc)"; exit 1; }
[ $rc = 0 ] || grep -q "missing" "$dir/convert.err" || { cat "$dir/convert.err"; echo "FAIL: exit 3 without the missing ones listed"; exit 1; }
grep "convert\|missing" "$dir/convert.err" | tail -3
"$gs" inspect "$dir/bus.mcap" | grep -E "^end|/$sid/state"
# the converted log, complete, read by MCAP's Python library: sound, every
# message valid against its schema, the messages its ledgers'
if mcap_py "$dir/bus.mcap" "$dir/py_bus.json"; then mcap_py_ledgers "$dir/py_bus.json"; fi
"$gs" convert "$dir/bus.mcap" "$dir/back.lcm" 2>&1 | tail -1
cmp "$dir/bus.lcm" "$dir/back.lcm" > /dev/null 2>&1 && echo "the log came back byte for byte" || {
  # event numbers and receive times differ (the MCAP keeps simulation time): compare the messages
  python3 - "$dir/bus.lcm" "$dir/back.lcm" <<'PY'
import struct, sys
def events(p):
    out, b = [], open(p, "rb").read()
    i = 0
    while i + 28 <= len(b):
        sync, num, ts, clen, dlen = struct.unpack(">IqqII", b[i:i + 28])
        assert sync == 0xEDA1DA01, "bad sync"
        ch = b[i + 28:i + 28 + clen]; data = b[i + 28 + clen:i + 28 + clen + dlen]
        out.append((ch, data)); i += 28 + clen + dlen
    return out
a, c = events(sys.argv[1]), events(sys.argv[2])
print(f"LCM log {len(a)} messages, back from MCAP {len(c)}")
sys.exit(0 if sorted(a) == sorted(c) else 1)
PY
} || { echo "FAIL: the messages did not come back"; exit 1; }
mcap_checks_done
