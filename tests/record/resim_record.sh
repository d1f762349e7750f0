#!/bin/sh
# `groundsim replay --resimulate` (issue 23, docs/logging.md): a real server
# and a real recorder; two sessions created after the recorder started, each
# driven while it runs:
#   plain.json (drive_t): throttle, turn, brake, then the driver leaves with
#     the torque held and the command timeout releases it; paused, resumed,
#     reset, driven again, stopped;
#   sedan.json (a road car with a control table): controls_t take over from
#     the table, the controls timeout releases the pedals, a reset hands the
#     car back to the table.
# Recorded --exact, each session re-simulates to identical states (every double, and the raw
# LCM bytes). Then copies of the file with one state's position nudged by one
# unit in the last place, and with one applied command left out, each report
# the first difference: the nudged state's seq and field, and the first state
# after the dropped command. The recording is also checked by MCAP's own
# Python library (tests/recording/mcap_py_check.py; not installed: the other
# checks, then SKIP, 77). Every wait is for a condition: states of a session
# (`watch --count`: simulated time, which in real time is at least as much
# wall time, so a wall-clock timeout of the server's has passed and been
# checked while the session ran), the recorder stopped once everything is
# done (was: 7 s of wall time, which a loaded machine's clients could miss).
#   resim_record.sh BUILD_DIR SOURCE_DIR     (inside tests/integration/netns_run.sh)
set -eu
build=$1; src=$2; gs=$build/client/groundsim; tamper=$build/tests/record/mcap_tamper
# requests wait 10 s for the reply (the CLI's 2 s is missed by a loaded server now and then)
rq() { cmd=$1; shift; "$gs" "$cmd" --timeout 10 "$@"; }
dir=$(mktemp -d)
# the background jobs (server, recorders, loggers) are ended on exit: $(jobs -p)
# in a command substitution lists none in dash, and the servers outlived the test
trap 'jobs -p > "$dir/.jobs"; kill $(cat "$dir/.jobs") 2>/dev/null || true; rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
. "$(dirname "$0")/resim_lib.sh"
. "$(dirname "$0")/mcap_checks.sh"
start_server --quiet
"$gs" record --all --raw --exact --out "$dir/run.mcap" 2> "$dir/rec.err" &
rec=$!
for _ in $(seq 600); do grep -q "recording to" "$dir/rec.err" && break; sleep 0.1; done
a=$(rq create "$src/configs/plain.json" --publish-rate 200 --duration 30 | tail -1)
b=$(rq create "$src/configs/sedan.json" --publish-rate 100 --duration 30 | tail -1)
[ -n "$a" ] && [ -n "$b" ] || fail "no sessions"
# the car: controls, then gone with the pedals held (timeout), then a reset
printf 'throttle 0.6\nsteer 0.3\nwait 0.6\nbrake 0.4\nthrottle 0\nwait 0.3\nquit\n' |
  "$gs" drive "$b" --controls car --hold > /dev/null 2>&1 &
car=$!
printf 'throttle 3\nwait 0.5\nturn 0.5\nwait 0.4\nbrake 2\nwait 0.2\nthrottle 4\nwait 0.3\nquit\n' |
  "$gs" drive "$a" --hold > /dev/null
# 0.8 s of its simulated time (200 states a second): the command timeout
# (0.5 s of wall time) has released the torque
rq watch "$a" --count 160 > /dev/null
rq pause "$a" > /dev/null; sleep 0.2; rq resume "$a" > /dev/null
rq watch "$a" --count 40 > /dev/null
rq reset "$a" > /dev/null
printf 'throttle 2\nturn -0.4\nwait 0.4\nrelease\nwait 0.1\nquit\n' | "$gs" drive "$a" > /dev/null
rq stop "$a" > /dev/null
wait $car
# 0.8 s of the car's (100 states a second): its controls timeout has released the pedals
rq watch "$b" --count 80 > /dev/null
rq reset "$b" > /dev/null
rq watch "$b" --count 50 > /dev/null
kill -INT $rec
wait $rec || true
grep "^record" "$dir/rec.err" | tail -4
"$gs" inspect "$dir/run.mcap" | grep -E "^end|/applied"
# MCAP's own Python library on a file with the raw LCM bytes (channels lcm/...,
# read, not decoded) and the players' commands: sound, every JSON message
# valid against its schema, the streams' messages the ledgers'
if mcap_py "$dir/run.mcap" "$dir/py.json"; then mcap_py_ledgers "$dir/py.json"; fi

for s in "$a" "$b"; do
  expect_identical "$dir/run.mcap" "$s"
  grep -q "^raw LCM bytes identical too" "$dir/same.txt" || fail "raw bytes not compared"
done
# the commands that took effect: drive, timeout, pause, resume, reset, stop, end;
# controls, controls timeout, reset
for k in '"kind":1,' '"kind":3,' '"kind":6,' '"kind":7,' '"kind":5,' '"kind":10,' '"kind":11,'; do
  "$tamper" "$dir/run.mcap" - find "/$a/applied" "$k" > /dev/null || fail "session $a: no applied entry $k"
done
for k in '"kind":2,' '"kind":4,' '"kind":5,'; do
  "$tamper" "$dir/run.mcap" - find "/$b/applied" "$k" > /dev/null || fail "session $b: no applied entry $k"
done

# replay --resimulate of $dir/NAME.mcap, session ID, into $dir/NAME.txt:
# it must exit 5 (a state differs)
differs_expected() {
  local name=$1 id=$2 what=$3 rc
  set +e
  "$gs" replay --resimulate "$dir/$name.mcap" --session "$id" > "$dir/$name.txt" 2>&1
  rc=$?
  set -e
  cat "$dir/$name.txt"
  [ $rc -eq 5 ] || fail "$what: exit $rc, not 5"
}

# one unit in the last place of one position, state seq 300 of the car
"$tamper" "$dir/run.mcap" "$dir/nudged.mcap" nudge "/$b/state" 300 > "$dir/nudge.txt"
read old new < "$dir/nudge.txt"
differs_expected nudged "$b" "a nudged state"
grep -q "^differs: session $b, state seq 300 .*: vehicles\[0\]\.position\[0\] recorded $new, re-simulated $old\$" \
  "$dir/nudged.txt" || fail "the nudged value ($old -> $new) is not the first difference named"

# the plain car's first throttle-3 drive left out, or if a loaded server
# applied the next one in the same tick (so that leaving it out changes
# nothing), its first throttle-4 one (with the turn: [2,6,2,6], 1.1 s later)
first=""
for torque in '[3,3,3,3]' '[2,6,2,6]'; do
  rc=0; first=$("$tamper" "$dir/run.mcap" - find-alone "/$a/applied" "\"drive_torque\":$torque") || rc=$?
  [ $rc = 0 ] && break
  [ $rc = 3 ] || fail "no drive of $torque N m applied"
  first=""
done
[ -n "$first" ] || fail "both the first throttle-3 and throttle-4 drives were superseded in their ticks: nothing to leave out"
"$tamper" "$dir/run.mcap" "$dir/dropped.mcap" drop "/$a/applied" "$first"
differs_expected dropped "$a" "a dropped command"
grep -q "applied commands $first\.\.$first are missing" "$dir/dropped.txt" || fail "the missing command is not named"
grep -q "^differs: session $a, state seq [0-9]* (t [0-9.e-]* s, tick [0-9]*): [a-z_]" "$dir/dropped.txt" ||
  fail "no state difference named after the dropped command"
mcap_checks_done
