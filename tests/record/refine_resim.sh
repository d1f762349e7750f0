#!/bin/sh
# A session that refined its step re-simulates bit for bit (docs/accuracy.md,
# Refinement): the sedan's slalom with a tolerance no setting meets, recorded
# --exact from its create. Its live estimate passes the tolerance at once,
# so the session refines twice at safe points (accuracy.max_refinements 2:
# 2, then 4 integrator substeps per step), each an applied REFINE entry,
# then warns once. `groundsim replay --resimulate` refines at the same ticks
# and reaches every recorded state bit for bit; a re-simulation that left
# the entries out would step the later states at the coarser step.
#   refine_resim.sh BUILD_DIR SOURCE_DIR     (inside tests/integration/netns_run.sh)
set -eu
build=$1; src=$2; gs=$build/client/groundsim; tamper=$build/tests/record/mcap_tamper
dir=$(mktemp -d)
# the background jobs (server, recorders, loggers) are ended on exit: $(jobs -p)
# in a command substitution lists none in dash, and the servers outlived the test
trap 'jobs -p > "$dir/.jobs"; kill $(cat "$dir/.jobs") 2>/dev/null || true; rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; tail -n 20 "$dir/server.out"; exit 1; }
export XDG_STATE_HOME="$dir"   # the tokens of this test's sessions
python3 - "$src/configs/sedan_slalom.json" "$dir/slalom.json" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["accuracy"] = {"tolerance": 1e-6, "pilot_duration": 1, "max_refinements": 2}
json.dump(doc, open(sys.argv[2], "w"))
PY
. "$(dirname "$0")/resim_lib.sh"
start_server
"$gs" record --create "$dir/slalom.json" --exact --session-duration 5 --out "$dir/refined.mcap" \
  > "$dir/rec.out" 2> "$dir/rec.err" || fail "the recorder exited $?: $(tail -n 3 "$dir/rec.err")"
sid=$(head -n 1 "$dir/rec.out")
[ -n "$sid" ] || fail "no session was created: $(cat "$dir/rec.err")"
"$tamper" "$dir/refined.mcap" - find "/$sid/applied" '"kind":13,' > /dev/null || fail "no applied REFINE entry in the file"
"$tamper" "$dir/refined.mcap" - find "/$sid/events" 'refined to 2 integrator substeps per step (from 1)' > /dev/null ||
  fail "no first refinement event in the file"
"$tamper" "$dir/refined.mcap" - find "/$sid/events" 'refined to 4 integrator substeps per step (from 2)' > /dev/null ||
  fail "no refinement event in the file"
"$tamper" "$dir/refined.mcap" - find "/$sid/events" 'max_refinements' > /dev/null ||
  fail "no warning naming max_refinements in the file"
expect_identical "$dir/refined.mcap" "$sid"
echo "PASS: a session refined twice at safe points re-simulates bit for bit"
