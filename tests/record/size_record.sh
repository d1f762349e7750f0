#!/bin/sh
# Size at most 25% of the same LCM log on the state stream (issue 23,
# docs/logging.md, Size): a real server, a real recorder (`record --create`
# of the sedan's slalom at 500 Hz, states and car states) and lcm-logger
# (LCM's own logger) logging the same channels, one file per stream. Checked:
#   - the state stream alone: `groundsim convert` of lcm-logger's log of the
#     state channel (the same messages, same bytes) is at most 25% of it;
#   - the whole recording (states, car states, applied commands, events,
#     ledgers, scenario, indexes) is at most 25% of the LCM log of the
#     messages it holds;
#   - the file says its precision (fields-1), opens in npm's @mcap/core with
#     its counts per channel equal to the ledger, passes MCAP's own Python
#     library (tests/recording/mcap_py_check.py: CRCs, indexes, statistics,
#     every message valid against its schema; its messages the ledger's, and
#     so for the converted state stream), and re-simulates to the same
#     states at that precision (`replay --resimulate`). Without either
#     reader installed: the other checks, then SKIP (77) naming it.
# The exact encoding's size (--exact) is printed beside, not checked.
#   size_record.sh BUILD_DIR SOURCE_DIR     (inside tests/integration/netns_run.sh)
set -eu
build=$(cd "$1" && pwd); src=$(cd "$2" && pwd); gs=$build/client/groundsim
dir=$(mktemp -d)
# the background jobs (server, recorders, loggers) are ended on exit: $(jobs -p)
# in a command substitution lists none in dash, and the servers outlived the test
trap 'jobs -p > "$dir/.jobs"; kill $(cat "$dir/.jobs") 2>/dev/null || true; rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
. "$src/tests/record/mcap_checks.sh"
"$build/server/lcm/groundsim-server" --quiet > "$dir/server.out" 2>&1 &
for _ in $(seq 50); do "$gs" list > /dev/null 2>&1 && break; sleep 0.1; done
lcm-logger --quiet -c 'GROUNDSIM_STATE_.*' "$dir/state.lcm" > /dev/null 2>&1 &
l1=$!
lcm-logger --quiet -c 'GROUNDSIM_CAR_STATE_.*' "$dir/car.lcm" > /dev/null 2>&1 &
l2=$!
sleep 0.5
rc=0
"$gs" record --create "$src/configs/sedan_slalom.json" --session-duration 8 --publish-rate 500 \
  --out "$dir/run.mcap" > "$dir/rec.out" 2> "$dir/rec.err" || rc=$?
grep "^record" "$dir/rec.err" | tail -3
[ $rc = 0 ] || { cat "$dir/rec.err"; fail "the recorder exited $rc"; }
sid=$(tail -1 "$dir/rec.out")
[ -n "$sid" ] || fail "no session"
sleep 0.3
kill $l1 $l2; wait $l1 $l2 2>/dev/null || true
"$gs" inspect "$dir/run.mcap" > "$dir/inspect.txt"
grep -q "^end *complete" "$dir/inspect.txt" || { cat "$dir/inspect.txt"; fail "the file is not complete"; }
# (exit 3: lcm-logger's queue dropped some, named in the converted file's
# ledger; the converted file holds the same messages as the log all the same)
for f in state exact; do
  rc=0
  "$gs" convert "$dir/state.lcm" "$dir/$f.mcap" --no-raw $([ $f = exact ] && echo --exact) 2> "$dir/convert.err" || rc=$?
  [ $rc = 0 ] || [ $rc = 3 ] || { cat "$dir/convert.err"; fail "convert ($f) exited $rc"; }
done
python3 - "$dir" "$sid" <<'PY' || fail "over 25% (above)"
import os, re, struct, sys
d, sid = sys.argv[1], sys.argv[2]
def lcm_log(p):
    """messages and bytes of an lcm-logger file, of the session's channels"""
    b, i, n = open(os.path.join(d, p), "rb").read(), 0, 0
    while i + 28 <= len(b):
        _, _, _, clen, dlen = struct.unpack(">IqqII", b[i:i + 28])
        n += b[i + 28:i + 28 + clen].decode().endswith(sid)
        i += 28 + clen + dlen
    return n, len(b)
size = lambda p: os.path.getsize(os.path.join(d, p))
inspect = open(os.path.join(d, "inspect.txt")).read()
count = lambda kind: int(re.search(r"^channel +/%s/%s +(\d+) messages" % (sid, kind), inspect, re.M).group(1))
(ns, bs), (nc, bc) = lcm_log("state.lcm"), lcm_log("car.lcm")
rs, rc = count("state"), count("car_state")
print(f"lcm-logger: {ns} states in {bs} bytes, {nc} car states in {bc} bytes; the recording: {rs} states, {rc} car states")
if min(ns, nc, rs, rc) < 1000:
    print(f"too few messages for a size measurement"); sys.exit(1)
alone, exact = size("state.mcap") / bs, size("exact.mcap") / bs
# the LCM log of exactly the messages the recording holds (lcm-logger's
# queue may drop a few: its bytes per message times the recording's count)
whole = size("run.mcap") / (bs / ns * rs + bc / nc * rc)
print(f"state stream: convert's MCAP {size('state.mcap')} bytes = {100 * alone:.1f}% of the LCM log "
      f"(--exact: {size('exact.mcap')} bytes = {100 * exact:.1f}%)")
print(f"the recording: {size('run.mcap')} bytes = {100 * whole:.1f}% of the LCM log of the states and car states it holds")
sys.exit(0 if alone <= 0.25 and whole <= 0.25 else 1)
PY
grep -q "^precision *fields-1 " "$dir/inspect.txt" || { cat "$dir/inspect.txt"; fail "the file does not say fields-1"; }
# npm's @mcap/core: the file opens, and its counts per channel equal the ledger
if mcap_node "$dir/run.mcap" "$dir/read.json"; then
  node -e '
    const r = JSON.parse(require("fs").readFileSync(process.argv[1])); const sid = process.argv[2];
    const l = r.metadataRecords["ledger/" + sid];
    const ok = (kind, prefix) => {
      const n = r.topics["/" + sid + "/" + kind], want = Number(l[prefix + "received_count"]) + Number(l[prefix + "repaired_count"]);
      console.log("@mcap/core:", kind, n, "messages, ledger", want);
      return n === want && l[prefix + "lost"] === "";
    };
    if (!l || !ok("state", "state_") || !ok("car_state", "car_state_")) { console.log("FAIL: counts differ from the ledger"); process.exit(1); }
  ' "$dir/read.json" "$sid"
fi
# MCAP's own Python library: the file sound (CRCs, indexes, statistics),
# every message valid against its schema, the messages the ledgers' (and
# the same for the state stream converted from lcm-logger's log)
if mcap_py "$dir/run.mcap" "$dir/py.json"; then
  mcap_py_ledgers "$dir/py.json"
  mcap_py "$dir/state.mcap" "$dir/py_state.json" && mcap_py_ledgers "$dir/py_state.json"
fi
# the states re-simulate, compared at the recorded precision
"$gs" replay --resimulate "$dir/run.mcap" > "$dir/replay.txt" 2>&1 || { cat "$dir/replay.txt"; fail "replay --resimulate"; }
cat "$dir/replay.txt"
grep -q "^identical: session $sid" "$dir/replay.txt" || fail "not identical"
grep -q "^compared at the recording's precision only: fields-1" "$dir/replay.txt" || fail "the precision is not named"
mcap_checks_done
