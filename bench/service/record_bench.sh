#!/bin/sh
# The recorder beside an independent subscriber (issue 23): N sessions
# publishing at R Hz for D s (plain.json at the balanced preset's 1 ms
# step), recorded by `groundsim record --all` while lcm-logger (LCM's own
# tool, another implementation) logs the same state channels. Prints the
# states each holds, any state lcm-logger has that the recording lacks (a
# silent loss: must be 0), the recorder's repaired/lost, CPU time and file
# size, and the size per state beside lcm-logger's log of the same states
# (the issue's "at most 25% of the same LCM log on the state stream").
# Extra `record` options (e.g. --exact, or --zstd-level 3) in RECORD_OPTS, another build
# folder in BUILD; KEEP=DIR keeps the two files there. Run inside a private network namespace:
#   tests/integration/netns_run.sh bench/service/record_bench.sh [N=20] [R=1000] [D=20]
set -eu
N=${1:-20}; R=${2:-1000}; D=${3:-20}
root=$(cd "$(dirname "$0")/../.." && pwd); build=${BUILD:-$root/build}; gs=$build/client/groundsim
dir=$(mktemp -d); trap 'kill $(jobs -p) 2>/dev/null || true; [ -z "${KEEP:-}" ] || cp "$dir/bus.lcm" "$dir/all.mcap" "$KEEP"/; rm -rf "$dir"' EXIT
"$build/server/lcm/groundsim-server" --quiet --max-sessions $((N + 4)) --client-sessions 0 --client-creates 0 > "$dir/server.out" 2>&1 &
for _ in $(seq 50); do "$gs" list > /dev/null 2>&1 && break; sleep 0.1; done
lcm-logger --quiet -c 'GROUNDSIM_STATE_.*' "$dir/bus.lcm" > /dev/null 2>&1 &
logger=$!
/usr/bin/time -f "%U %S" -o "$dir/rec.time" "$gs" record --all ${RECORD_OPTS:-} --out "$dir/all.mcap" --duration $((D + 6)) \
  2> "$dir/rec.err" &
for _ in $(seq 100); do grep -q "record: recording" "$dir/rec.err" && break; sleep 0.1; done
ids=""
for i in $(seq $N); do
  ids="$ids $("$gs" create "$root/configs/plain.json" --preset balanced --publish-rate $R --duration $D | tail -1)"
done
for _ in $(seq 600); do [ -s "$dir/rec.time" ] && break; sleep 0.1; done
kill $logger; sleep 0.3
echo "sessions $N x $R Hz x $D s"
grep "^record: .* messages received" "$dir/rec.err"
echo "recorder CPU (user sys, s): $(cat "$dir/rec.time")"
echo "file: $(stat -c %s "$dir/all.mcap") bytes"
"$gs" inspect "$dir/all.mcap" | awk '$2 ~ /\/state$/ {n += $3} END {print "in the recording: " n " states"}'
# every (session, seq) lcm-logger holds must be in the recording
"$gs" convert "$dir/all.mcap" /dev/null > /dev/null 2>&1 || true
python3 - "$dir/bus.lcm" "$dir/all.mcap" "$gs" <<'PY'
import json, struct, subprocess, sys
def lcm_states(p):
    seen, b, i = set(), open(p, "rb").read(), 0
    while i + 28 <= len(b):
        sync, num, ts, clen, dlen = struct.unpack(">IqqII", b[i:i + 28])
        ch = b[i + 28:i + 28 + clen].decode(); d = b[i + 28 + clen:i + 28 + clen + dlen]
        seen.add((ch[len("GROUNDSIM_STATE_"):], struct.unpack(">q", d[16:24])[0]))
        i += 28 + clen + dlen
    return seen
logged = lcm_states(sys.argv[1])
out = subprocess.run([sys.argv[3], "inspect", sys.argv[2]], capture_output=True, text=True).stdout
recorded = {}
for line in out.splitlines():
    if line.startswith("ledger/") and not line.startswith("ledger/events"):
        sid = line.split()[0][len("ledger/"):]
        kv = dict(x.strip().split(" ", 1) for x in line.split(None, 1)[1].split(", "))
        recorded[sid] = (int(kv["state_received_count"]), int(kv["state_repaired_count"]), kv["state_lost"])
print(f"lcm-logger: {len(logged)} states")
missing = [k for k in logged if k[0] not in recorded]
print(f"states lcm-logger has from sessions the recording lacks: {len(missing)}")
# size per state: the MCAP file (states, events, ledgers, indexes: all of it)
# against lcm-logger's log (states only), each divided by the states it holds
import os
n_rec = sum(r[0] + r[1] for r in recorded.values())
mb, lb = os.path.getsize(sys.argv[2]), os.path.getsize(sys.argv[1])
print(f"bytes per state: MCAP {mb / n_rec:.1f}, LCM log {lb / len(logged):.1f}: "
      f"the MCAP is {100 * (mb / n_rec) / (lb / len(logged)):.1f}% of the LCM log")
PY
