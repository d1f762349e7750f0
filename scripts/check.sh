#!/usr/bin/env bash
# Everything CI runs (.ci/run): the test suite (Release), the whole suite
# under ASan + UBSan, the integration tests under TSan, and a short fuzz run
# of each libFuzzer target. Stops at the first failure. Each stage prints
# its wall time.
#   FUZZ_SECONDS=60 (default) seconds per fuzz target
set -euo pipefail
cd "$(dirname "$0")/.."

stage() {
  local start=$SECONDS
  echo "=== check: $*"
  "$@"
  echo "=== check: $* passed in $((SECONDS - start)) s"
}

stage scripts/test.sh
stage scripts/test.sh --sanitize=address,undefined
stage scripts/test.sh --sanitize=thread
stage scripts/fuzz.sh --seconds "${FUZZ_SECONDS:-60}"
echo "=== check: all passed in $SECONDS s"
