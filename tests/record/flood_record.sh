#!/bin/sh
# The recorder's accounting at the issue's scale (issue 23: "100 sessions x
# 2 kHz x 60 s with bursts, recorded beside an independent subscriber: the
# ledger's counts equal the subscriber's, every loss is listed, none
# silent"), without the physics: record_flood publishes real encoded
# state_t for N sessions at R Hz each for D s, with bursts (every 5 s,
# or 2 s in a run under 20 s, 0.5 s at 4 times the rate), a heartbeat listing every session's newest
# seq, and each session's END entry and FINISHED state; it keeps what it
# published in the server's ResendRing and answers re-requests.
# `groundsim record --all` records beside record_state_counter (an
# independent subscriber, its own socket). record_flood_check then reads
# the whole file back and checks, per session: every seq published is
# received, repaired or lost in the ledger, exactly once; the file holds
# exactly the received and repaired ones; every seq the subscriber heard
# is in the file or listed lost; the subscriber's heard + missed is what
# was published; every seq listed repaired is one the flood's ring resent.
# The recorder is stalled while the flood goes on, so it must miss seqs
# live: with the ring some of them are repaired, without it (--no-ring)
# none is and all are listed lost. How much is lost depends on the
# machine, and is printed, never asserted.
#   flood_record.sh BUILD_DIR SOURCE_DIR [N=100] [R=2000] [D=5]   (inside tests/integration/netns_run.sh)
# FLOOD_OPTS: more record_flood options (e.g. --no-ring); REPAIR_WAIT: record's
# --repair-wait (20 s); RECORD_OPTS:
# more `record` options; KEEP=DIR keeps the file and the reports.
set -eu
build=$(cd "$1" && pwd); src=$(cd "$2" && pwd); N=${3:-100}; R=${4:-2000}; D=${5:-5}
gs=$build/client/groundsim; tools=$build/tests/record
for b in "$gs" "$tools/record_flood" "$tools/record_state_counter" "$tools/record_flood_check"; do
  [ -x "$b" ] || { echo "FAIL: $b is not built"; exit 1; }
done
dir=$(mktemp -d)
flood=""; counter=""; rec=""
trap 'code=$?; set +e; for p in $rec $counter $flood; do kill $p 2>/dev/null; done
      [ -z "${KEEP:-}" ] || cp "$dir"/*.mcap "$dir"/*.json "$dir"/*.err "$KEEP"/ 2>/dev/null; rm -rf "$dir"; exit $code' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# bursts every 5 s (every 2 s in runs under 20 s), 0.5 s at 4 times the rate
burst=5; [ "$D" -ge 20 ] || burst=2
"$tools/record_flood" --sessions "$N" --rate "$R" --duration "$D" --burst-every $burst --go "$dir/go" --report "$dir/flood.json" \
  --linger 300 ${FLOOD_OPTS:-} 2> "$dir/flood.err" &
flood=$!
"$tools/record_state_counter" --out "$dir/counter.json" 2> "$dir/counter.err" &
counter=$!
/usr/bin/time -f "%e %U %S %M" -o "$dir/rec.time" \
  "$gs" record --all --out "$dir/all.mcap" --repair-wait ${REPAIR_WAIT:-20} ${RECORD_OPTS:-} 2> "$dir/rec.err" &
timer=$!
for _ in $(seq 50); do rec=$(pgrep -P $timer || true); [ -n "$rec" ] && break; sleep 0.1; done
[ -n "$rec" ] || fail "the recorder did not start"
for _ in $(seq 300); do
  grep -qs "record: recording" "$dir/rec.err" && grep -qs listening "$dir/counter.err" && break
  sleep 0.1
done
grep -qs "record: recording" "$dir/rec.err" || { cat "$dir/rec.err"; fail "the recorder did not start"; }
cp /proc/net/snmp "$dir/snmp.before"
touch "$dir/go"
# The recorder is stopped while it is behind the bus: it stalls (SIGSTOP)
# for the flood's last 2 s, and is stopped (SIGINT) the moment it resumes,
# with states and heartbeats still queued in its socket; it must account
# for every seq published before the stop (it asks for the tail, and
# waits for repairs still outstanding: --repair-wait)
sleep $((D - 2))
kill -STOP $rec
for _ in $(seq $(( (D + 120) * 10 ))); do [ -s "$dir/flood.json" ] && break; sleep 0.1; done
kill -CONT $rec
[ -s "$dir/flood.json" ] || fail "the flood did not end"
# kernel drops per socket (/proc/net/udp's last column), before anyone exits
drops=$(awk 'NR > 1 {n += $NF} END {print n + 0}' /proc/net/udp)
for p in $rec $counter $flood; do
  for fd in /proc/$p/fd/*; do
    ino=$(readlink "$fd" 2>/dev/null | sed -n 's/^socket:\[\([0-9]*\)\]$/\1/p')
    [ -n "$ino" ] || continue
    d=$(awk -v i="$ino" 'NR > 1 && $10 == i {print $NF}' /proc/net/udp)
    [ -n "$d" ] && echo "$p $d" >> "$dir/drops"
  done
done
kill -INT $rec 2>/dev/null || true
rc=0; wait $timer || rc=$?
kill -INT $counter 2>/dev/null || true; wait $counter || true
kill -INT $flood 2>/dev/null || true; wait $flood || true
cp /proc/net/snmp "$dir/snmp.after"
[ $rc = 0 ] || [ $rc = 3 ] || { tail -5 "$dir/rec.err"; fail "the recorder exited $rc"; }

echo "flood: $(grep 'states in' "$dir/flood.err" | sed 's/^record_flood: //')"
echo "flood: $(grep 'resend requests' "$dir/flood.err" | sed 's/^record_flood: //')"
grep "^record: .* messages received" "$dir/rec.err" || true
echo "record: $(grep -c '^record [0-9A-F]* states: .* lost [1-9]' "$dir/rec.err" || true) sessions named with losses on stderr; exit $rc"
set -- $(tail -1 "$dir/rec.time")
echo "recorder: $1 s wall, $2 s user, $3 s system CPU, $4 kB max resident"
echo "file: $(stat -c %s "$dir/all.mcap") bytes"
recdrops=$(awk -v p=$rec '$1 == p {n += $2} END {print n + 0}' "$dir/drops" 2>/dev/null || echo 0)
cntdrops=$(awk -v p=$counter '$1 == p {n += $2} END {print n + 0}' "$dir/drops" 2>/dev/null || echo 0)
rcvbuf() { awk '/^Udp:/ {if (!h) {for (i = 1; i <= NF; i++) if ($i == "RcvbufErrors") c = i; h = 1} else print $c}' "$1"; }
flddrops=$(awk -v p=$flood '$1 == p {n += $2} END {print n + 0}' "$dir/drops" 2>/dev/null || echo 0)
echo "kernel: datagrams dropped at full socket buffers: recorder's socket $recdrops, subscriber's $cntdrops," \
  "the flood's (it hears the stream too, for the re-requests) $flddrops, all sockets $drops (Udp RcvbufErrors $(( $(rcvbuf "$dir/snmp.after") - $(rcvbuf "$dir/snmp.before") )))"
"$tools/record_flood_check" "$dir/all.mcap" "$dir/flood.json" "$dir/counter.json" || fail "the accounting"
# the recorder's own summary agrees with the file: exit 3 exactly when it lost something
lost=$(grep "^record: .* messages received" "$dir/rec.err" | sed 's/.* repaired, \([0-9]*\) lost.*/\1/')
{ [ "$lost" -gt 0 ] && [ $rc = 3 ]; } || { [ "$lost" = 0 ] && [ $rc = 0 ]; } || fail "exit $rc with $lost lost"
echo PASS
