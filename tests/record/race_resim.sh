#!/bin/sh
# A recorded race re-simulates bit for bit (docs/logging.md, Re-simulation):
# the sprint stage of tests/web/data/race (gates at x = 10, 40, 70 m, a 3 s
# countdown) recorded --exact from its create while `groundsim drive` holds
# full throttle from the first instant: the server holds the car through
# the countdown (its applied log still lists the driver's throttle), lets it
# go at 3 s; `groundsim respawn` puts it back at its last gate mid-run (an
# applied RESPAWN entry), and it is driven on. `groundsim replay
# --resimulate` runs the same race beside the log (the hold, go, the
# respawn at the same spot) and reaches every recorded state bit for bit.
# Without the race in the re-simulation the first state after the driver's
# throttle differs.
#   race_resim.sh BUILD_DIR SOURCE_DIR     (inside tests/integration/netns_run.sh)
set -eu
build=$1; src=$2; gs=$build/client/groundsim; tamper=$build/tests/record/mcap_tamper
dir=$(mktemp -d)
# the background jobs (server, recorders, loggers) are ended on exit: $(jobs -p)
# in a command substitution lists none in dash, and the servers outlived the test
trap 'jobs -p > "$dir/.jobs"; kill $(cat "$dir/.jobs") 2>/dev/null || true; rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; tail -n 20 "$dir/server.out"; exit 1; }
export XDG_STATE_HOME="$dir"   # the tokens of this test's sessions
. "$(dirname "$0")/resim_lib.sh"
start_server
"$gs" record --create "$src/tests/web/data/race/sprint.json" --exact --session-duration 11 --publish-rate 100 \
  --out "$dir/race.mcap" > "$dir/rec.out" 2> "$dir/rec.err" &
rec=$!
for _ in $(seq 100); do [ -s "$dir/rec.out" ] && break; sleep 0.1; done
sid=$(head -n 1 "$dir/rec.out")
[ -n "$sid" ] || fail "no session was created: $(cat "$dir/rec.err")"
# full throttle from the countdown on; the car passes the first gate (10 m)
# about 2 s after go (3 s), the second (40 m) about 2.5 s later
printf 'throttle 1\nwait 6.2\nquit\n' | "$gs" drive "$sid" --controls car --hold > /dev/null 2>&1
"$gs" respawn "$sid" > /dev/null || fail "respawn refused"
printf 'throttle 0.5\nsteer 0.2\nwait 1.5\nquit\n' | "$gs" drive "$sid" --controls car --hold > /dev/null 2>&1
wait $rec || fail "the recorder exited $?: $(tail -n 3 "$dir/rec.err")"
grep -q '"type":"respawn"' "$dir/server.out" || fail "the server did not respawn the car"
"$tamper" "$dir/race.mcap" - find "/$sid/applied" '"kind":12,' > /dev/null || fail "no applied RESPAWN entry in the file"
"$tamper" "$dir/race.mcap" - find "/$sid/applied" '"kind":2,' > /dev/null || fail "no applied controls in the file"
grep '"type":"respawn"' "$dir/server.out" | head -n 1
expect_identical "$dir/race.mcap" "$sid"
echo "PASS: a race with its countdown and a respawn re-simulates bit for bit"
