#!/usr/bin/env bash
# The main job: install what is missing, build, and run the report's
# plain-ground experiment (S1) in the embedded runner, ending with its
# summary and a speed plot like the report's figure 2.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p out
scenario="${1:-configs/plain.json}"
name="$(basename "$scenario" .json)"
build/client/groundsim run "$scenario" --csv "out/$name.csv" --plot "out/$name.png"
echo "csv: out/$name.csv   plot: out/$name.png"
