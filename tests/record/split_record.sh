#!/bin/sh
# A recording split into parts (`record --split-s`, docs/logging.md "How to
# record") read part by part by three MCAP readers: a real server, a real
# recorder (`record --create` of the sedan's slalom at 200 Hz for 7 s, a new
# part every 2 s of wall time). Checked:
#   - at least three parts <out>_0.mcap, <out>_1.mcap ..., each complete by
#     our reader (`groundsim inspect`);
#   - each opens on its own in npm's @mcap/core and in MCAP's own Python
#     library (tests/recording/mcap_py_check.py: CRCs, indexes, statistics,
#     every message valid against its schema), with the scenario attached
#     and the session's ledger;
#   - the parts' messages together are the last part's ledgers' received +
#     repaired, each seq once, and the states every seq from 0 to the newest.
# A reader not installed: the other checks, then SKIP (77) naming it.
#   split_record.sh BUILD_DIR SOURCE_DIR     (inside tests/integration/netns_run.sh)
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
rc=0
"$gs" record --create "$src/configs/sedan_slalom.json" --session-duration 7 --publish-rate 200 --split-s 2 \
  --out "$dir/run.mcap" > "$dir/rec.out" 2> "$dir/rec.err" || rc=$?
grep "^record" "$dir/rec.err" | tail -6
[ $rc = 0 ] || { cat "$dir/rec.err"; fail "the recorder exited $rc"; }
sid=$(tail -1 "$dir/rec.out")
[ -n "$sid" ] || fail "no session"
[ ! -e "$dir/run.mcap" ] || fail "--split-s wrote run.mcap itself, not parts"
n=0
while [ -f "$dir/run_$n.mcap" ]; do n=$((n + 1)); done
echo "$n parts: $(ls "$dir" | grep -c '\.mcap$') .mcap files"
[ "$n" -ge 3 ] || fail "$n parts of a 7 s recording split every 2 s"
[ "$(ls "$dir" | grep -c '\.mcap$')" = "$n" ] || { ls "$dir"; fail "parts not numbered 0..$((n - 1))"; }
reports=""
k=0
while [ $k -lt $n ]; do
  part=$dir/run_$k.mcap
  "$gs" inspect "$part" > "$dir/inspect_$k.txt" || { cat "$dir/inspect_$k.txt"; fail "inspect part $k"; }
  grep -q "^end *complete" "$dir/inspect_$k.txt" || { cat "$dir/inspect_$k.txt"; fail "part $k is not complete"; }
  if mcap_node "$part" "$dir/node_$k.json"; then
    node -e '
      const r = JSON.parse(require("fs").readFileSync(process.argv[1])); const sid = process.argv[2];
      const n = r.topics["/" + sid + "/state"] ?? 0;
      console.log("@mcap/core, part", process.argv[3] + ":", n, "states,", JSON.stringify(r.attachments));
      if (!r.attachments.includes("scenario/" + sid + ".json") || !r.metadataRecords["ledger/" + sid]) {
        console.log("FAIL: the part lacks the scenario or the ledger"); process.exit(1);
      }
    ' "$dir/node_$k.json" "$sid" "$k"
  fi
  if mcap_py "$part" "$dir/py_$k.json"; then
    python3 - "$dir/py_$k.json" "$sid" <<'PY' || fail "part $k lacks the scenario or the ledger"
import json, sys
r, sid = json.load(open(sys.argv[1])), sys.argv[2]
sys.exit(0 if f"scenario/{sid}.json" in r["attachments"] and f"ledger/{sid}" in r["metadataRecords"] else 1)
PY
    reports="$reports $dir/py_$k.json"
  fi
  k=$((k + 1))
done
if [ -n "$reports" ]; then
  # (word splitting of $reports: mktemp's paths have no spaces)
  mcap_py_ledgers $reports
  python3 - "$sid" $reports <<'PY' || fail "the parts do not hold every state seq from 0 to the newest"
import json, sys
sid, reports = sys.argv[1], [json.load(open(p)) for p in sys.argv[2:]]
l = reports[-1]["metadataRecords"][f"ledger/{sid}"]
counts = [r["topics"].get(f"/{sid}/state", 0) for r in reports]
print(f"states per part {counts}, {sum(counts)} in all; the last ledger: first {l['state_first']}, newest "
      f"{l['state_newest']}, lost {l['state_lost'] or 'none'}")
sys.exit(0 if l["state_first"] == "0" and l["state_lost"] == "" and sum(counts) == int(l["state_newest"]) + 1 else 1)
PY
fi
mcap_checks_done
