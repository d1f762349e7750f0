#!/usr/bin/env bash
# Configures and builds everything (Release) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
"$(dirname "$0")/setup.sh"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
# 2 jobs: the Eigen-heavy units need ~1 GB each and the CI machine has 2 cores
ninja -C build -j "${JOBS:-2}"
