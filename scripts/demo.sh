#!/usr/bin/env bash
# The main job: install what is missing (only what this runs), build only the
# embedded runner `groundsim`, and run the report's plain-ground experiment
# (S1), ending with its summary and a speed plot like the report's figure 2.
#   scripts/demo.sh [SCENARIO]   (default configs/plain.json)
# scripts/build.sh builds everything (servers, bridge, page, tests, benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --build-only
. scripts/lib/install_missing.sh
install_missing demo gnuplot-nox   # --plot draws with gnuplot
. scripts/lib/build_dir.sh
# no tests or benchmarks: their libraries (GoogleTest, Google Benchmark) are not installed by --build-only
build_dir build groundsim -DCMAKE_BUILD_TYPE=Release -DGROUNDSIM_BUILD_TESTS=OFF -DGROUNDSIM_BUILD_BENCH=OFF
mkdir -p out
scenario="${1:-configs/plain.json}"
name="$(basename "$scenario" .json)"
build/client/groundsim run "$scenario" --csv "out/$name.csv" --plot "out/$name.png"
echo "csv: out/$name.csv   plot: out/$name.png"
