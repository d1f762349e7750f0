#!/bin/sh
# The issue's full check (issue 23): 100 sessions x 2 kHz x 60 s with
# bursts (every 5 s, 0.5 s at 4 times the rate), recorded by `groundsim
# record --all` beside an independent subscriber, with the figures: states
# a second published, the ledger's received / repaired / lost against what
# was published and what the subscriber heard, kernel drops, the
# recorder's CPU and the file's size. The same script as the CTest
# record.FloodLedgerAccountsForEverySeq (tests/record/flood_record.sh),
# at full scale; it fails when anything is unaccounted for.
#   bench/record/flood_bench.sh [N=100] [R=2000] [D=60]     (BUILD: the build folder, default build)
# Output also to bench/results/<date>-record-flood-<N>x<R>x<D>.txt.
set -eu
N=${1:-100}; R=${2:-2000}; D=${3:-60}
root=$(cd "$(dirname "$0")/../.." && pwd); build=${BUILD:-$root/build}
out=$root/bench/results/$(date -u +%Y-%m-%d)-record-flood-${N}x${R}x${D}.txt
rc=$(mktemp)
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(git -C "$root" rev-parse --short HEAD), load $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# BUILD=$build bench/record/flood_bench.sh $N $R $D ${FLOOD_OPTS:+FLOOD_OPTS=\"$FLOOD_OPTS\"}"
  "$root/tests/integration/netns_run.sh" "$root/tests/record/flood_record.sh" "$build" "$root" "$N" "$R" "$D" 2>&1 && echo 0 > "$rc" || echo $? > "$rc"
} | tee "$out"
code=$(cat "$rc"); rm -f "$rc"; exit "$code"
