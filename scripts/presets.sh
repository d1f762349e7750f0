#!/usr/bin/env bash
# Error and speed of each preset on the two reference scenes:
#   downhill: acceleration fitted to speed over 0.5-2 s vs 3.8111 m/s^2
#   plain:    forward speed at 5 s vs 1.1111 m/s
#   speed:    sim-s per wall-s of a 200 s plain run (one core, this process only)
set -euo pipefail
cd "$(dirname "$0")/.."
G=build/client/groundsim
printf "%-9s %-14s %-10s %-14s %-10s %s\n" preset downhill_a err plain_v err sim-s/wall-s
for p in fast balanced accurate; do
  $G run configs/downhill.json --preset "$p" --quiet --csv /tmp/gs_dh.csv
  a=$(awk -F, 'NR>1 && $1>=0.5 && $1<=2 {n++; st+=$1; sv+=$8; stt+=$1*$1; stv+=$1*$8}
       END {printf "%.5f", (n*stv-st*sv)/(n*stt-st*st)}' /tmp/gs_dh.csv)
  $G run configs/plain.json --preset "$p" --quiet --csv /tmp/gs_pl.csv
  v=$(tail -1 /tmp/gs_pl.csv | cut -d, -f5)
  r=$($G run configs/plain.json --preset "$p" --duration 200 | awk '/wall time/ {print $(NF-3)}')
  printf "%-9s %-14s %-10s %-14s %-10s %s\n" "$p" "$a" \
    "$(awk -v a="$a" 'BEGIN{printf "%+.3f%%", (a/3.8111111-1)*100}')" "$(printf %.5f "$v")" \
    "$(awk -v v="$v" 'BEGIN{printf "%+.3f%%", (v/1.1111111-1)*100}')" "$r"
done
