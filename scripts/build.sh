#!/usr/bin/env bash
# Configures and builds everything (Release) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
. scripts/lib/build_dir.sh
build_dir build "" -DCMAKE_BUILD_TYPE=Release
