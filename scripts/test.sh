#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit, CLI and the
# LCM integration tests, each in its own network namespace).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
ctest --test-dir build --output-on-failure -j "${JOBS:-2}" --timeout 600 "$@"
