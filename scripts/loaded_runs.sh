#!/usr/bin/env bash
# The plain suite N times in a row while a load generator keeps every core
# busy (docs/reliability.md, "Loaded runs"): a test that depends on the
# machine's speed fails here. Uses build/ as built (scripts/build.sh first).
#   scripts/loaded_runs.sh [N=20] [ctest args...]
# Load: one busy loop per core at nice 10 (`nice -n 10 sh -c 'while :; do :; done'`),
# so the suite competes with it for every core. Prints one line per run and
# a summary; exits 1 if any run failed. Logs: build/loaded-runs/run-K.log.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-20}
shift || true
out=build/loaded-runs
mkdir -p "$out"
load=()
for _ in $(seq "$(nproc)"); do
  nice -n 10 sh -c 'while :; do :; done' &
  load+=($!)
done
trap 'kill "${load[@]}" 2>/dev/null || true' EXIT
failed=0
for k in $(seq "$runs"); do
  start=$SECONDS
  rc=0
  ctest --test-dir build --output-on-failure -j "${JOBS:-2}" --timeout 600 "$@" > "$out/run-$k.log" 2>&1 || rc=$?
  summary=$(grep -E '^[0-9]+% tests passed' "$out/run-$k.log" || echo "no summary")
  echo "run $k/$runs: rc $rc, $summary, $((SECONDS - start)) s, load average $(cut -d' ' -f1 /proc/loadavg)"
  if [ $rc -ne 0 ]; then
    failed=$((failed + 1))
    sed -n '/The following tests FAILED/,$p' "$out/run-$k.log"
  fi
done
echo "loaded runs: $runs, failed: $failed"
[ $failed -eq 0 ]
