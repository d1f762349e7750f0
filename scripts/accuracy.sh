#!/usr/bin/env bash
# Runs the accuracy sweep: its full report to bench/results/DATE-accuracy-sweep.md
# (docs/accuracy.md, the reference, is written by hand from it), and
# regenerates docs/img/work_precision.png,
# docs/img/road_work_precision.png (the sedan's manoeuvres) and
# docs/img/stability_map.png: builds bench/accuracy/tradeoff in its own build
# directory and runs the whole sweep (about 10 minutes on 2 cores).
#   scripts/accuracy.sh            full sweep
#   scripts/accuracy.sh --quick    small grids, output under /tmp (smoke test)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-accuracy}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C "$build" tradeoff
cd "$root"
if [[ "${1:-}" == "--quick" ]]; then
  out=$(mktemp -d)
  "$build/bench/accuracy/tradeoff" --quick --jobs "${JOBS:-2}" --out "$out" --docs "$out/accuracy.md" --img "$out/img"
  echo "quick run written to $out"
else
  report=bench/results/$(date -u +%F)-accuracy-sweep.md
  "$build/bench/accuracy/tradeoff" --jobs "${JOBS:-2}" --out build-accuracy/accuracy-out --docs "$report" --img docs/img
  echo "report written to $report; update docs/accuracy.md's tables from it"
fi
