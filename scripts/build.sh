#!/usr/bin/env bash
# Configures and builds everything (Release) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
. scripts/lib/build_dir.sh
# tests and benchmarks ON explicitly: scripts/demo.sh configures the same directory without them
build_dir build "" -DCMAKE_BUILD_TYPE=Release -DGROUNDSIM_BUILD_TESTS=ON -DGROUNDSIM_BUILD_BENCH=ON
