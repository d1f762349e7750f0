#!/bin/sh
# A 10-minute, 8-car recording in the browser: open and seek times
# (replay_bench.mjs), in a private network namespace. Timing only.
# Usage: bench/web/replay_bench.sh [SEEKS=20] [OPENS=5] [--mcap FILE] [--render0]
#   --mcap FILE: serve this recording instead of recording one (the session's first)
#   --render0: the page with ?render=0 (no drawing: the software renderer's frame time out)
# from the source tree, after building groundsim-server, groundsim,
# groundsim-web and the page (groundsim_web_page) in $BUILD (default build/).
# Writes bench/results/<date>-replay-bench.txt (RESULTS=FILE to change it).
set -e
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
OUT=${RESULTS:-$PWD/bench/results/$(date -u +%F)-replay-bench.txt}
export GROUNDSIM_SERVER=$PWD/$B/server/lcm/groundsim-server GROUNDSIM_WEB=$PWD/$B/web/bridge/groundsim-web \
       GROUNDSIM_CLI=$PWD/$B/client/groundsim GROUNDSIM_CONFIG_DIR=$PWD/configs GROUNDSIM_WEB_NODE_MODULES=$PWD/$B/web/node_modules
exec tests/integration/netns_run.sh node bench/web/replay_bench.mjs "$@" --out "$OUT"
