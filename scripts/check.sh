#!/usr/bin/env bash
# Every gate CI runs: the test suite (Release), the in-process and CLI tests
# under ASan + UBSan, the integration and session tests under TSan, and a
# short fuzz run of each libFuzzer target (docs/reliability.md, CI, has what
# each covers). Stops at the first failure. Each stage prints its wall time.
#   scripts/check.sh                 all four stages
#   scripts/check.sh --gates-only    the last three (.ci/run runs scripts/test.sh first)
#   FUZZ_SECONDS=60 (default) seconds per fuzz target
set -euo pipefail
cd "$(dirname "$0")/.."

plain=1
case "${1:-}" in
  "") ;;
  --gates-only) plain=0 ;;
  *) echo "usage: scripts/check.sh [--gates-only]" >&2; exit 2 ;;
esac

stage() {
  local start=$SECONDS
  echo "=== check: $*"
  "$@"
  echo "=== check: $* passed in $((SECONDS - start)) s"
}

[ $plain = 1 ] && stage scripts/test.sh
stage scripts/test.sh --sanitize=address,undefined
stage scripts/test.sh --sanitize=thread
stage scripts/fuzz.sh --seconds "${FUZZ_SECONDS:-60}"
echo "=== check: all passed in $SECONDS s"
