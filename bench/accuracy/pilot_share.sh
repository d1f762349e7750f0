#!/usr/bin/env bash
# The pilot's cost against the run it prepares: each scene run for 60 s
# (or --duration S) with `groundsim run --tolerance`, the pilot's and the
# run's wall time and work units, a row per scene and tolerance. The bar of
# docs/accuracy.md: the pilot at most 20% of a 60 s run. --share S sets
# accuracy.pilot_share (default 0: the whole scene is piloted).
#   bench/accuracy/pilot_share.sh [--duration S] [--share S] [--tolerances "0.1 0.01 0.001"] [SCENE.json ...]
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=build/client/groundsim
duration=60
share=0
tolerances="0.1 0.01 0.001"
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --duration) duration=$2; shift 2 ;;
    --tolerances) tolerances=$2; shift 2 ;;
    --share) share=$2; shift 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
[ ${#scenes[@]} -gt 0 ] || scenes=(configs/cosine.json configs/downhill.json configs/sedan_slalom.json
  configs/sedan_skidpad.json configs/sedan_stick_slip.json configs/contact/crash.json configs/accuracy/lone_wheel.json
  configs/accuracy/deformable_tyres.json configs/accuracy/eight_cars.json)
[ -x "$bin" ] || { echo "build $bin first (scripts/build.sh)" >&2; exit 2; }

printf '| scene | tolerance | pilot segment s | pilot wall s | run wall s | pilot / run (wall) | pilot / run (work) | chosen |\n'
printf '|---|---|---|---|---|---|---|---|\n'
for scene in "${scenes[@]}"; do
  for tol in $tolerances; do
    out=$("$bin" run "$scene" --duration "$duration" --tolerance "$tol" --set accuracy.pilot_share="$share" 2>/dev/null)
    pilot=$(sed -n 's/^pilot      \([^ ]*\) s of the scene per trial, \([^ ]*\) s wall.*/\1 \2/p' <<<"$out")
    run=$(sed -n 's/^wall time  \([^ ]*\) s:.*/\1/p' <<<"$out")
    work=$(sed -n 's/^pilot work [^ ]* work units, \([0-9]*\)%.*/\1/p' <<<"$out")
    chosen=$(sed -n 's/^accuracy   tolerance [^:]*: \(.*\) at dt \([^ ]*\) s.*/\1 \2/p' <<<"$out" | sed -e 's/ (local tolerance.*)//' -e 's/^model \([^ ]*\) (.*) with /\1: /')
    read -r segment pwall <<<"$pilot"
    ratio=$(awk -v p="$pwall" -v r="$run" 'BEGIN { printf "%.0f%%", 100 * p / r }')
    printf '| %s | %s | %s | %s | %s | %s | %s%% | %s |\n' "$(basename "$scene" .json)" "$tol" "$segment" "$pwall" "$run" \
      "$ratio" "$work" "$chosen"
  done
done
