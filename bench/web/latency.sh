#!/bin/sh
# Key press -> state latency of the browser front end (latency.mjs), in a
# private network namespace. Usage: bench/web/latency.sh [TRIALS] [norender] [trace]
# (trace: a breakdown per hop, from GROUNDSIM_TRACE stamps of the server and the bridge)
# from the source tree, after building groundsim-server, groundsim and groundsim-web in build/.
set -e
cd "$(dirname "$0")/../.."
B=${BUILD:-build}
export GROUNDSIM_SERVER=$PWD/$B/server/lcm/groundsim-server GROUNDSIM_WEB=$PWD/$B/web/bridge/groundsim-web \
       GROUNDSIM_CLI=$PWD/$B/client/groundsim GROUNDSIM_CONFIG_DIR=$PWD/configs GROUNDSIM_WEB_NODE_MODULES=$PWD/$B/web/node_modules
exec tests/integration/netns_run.sh node bench/web/latency.mjs "$@"
