#!/usr/bin/env bash
# One command for the browser front end: builds what is missing, starts
# groundsim-server and groundsim-web on this machine's LCM bus, prints the
# URL to open, and stops both on Ctrl-C.
#   scripts/web.sh [--port 8080] [more groundsim-web options]
set -euo pipefail
cd "$(dirname "$0")/.."
B=${BUILD:-build}
if [ ! -x "$B/web/bridge/groundsim-web" ] || [ ! -x "$B/server/lcm/groundsim-server" ] || [ ! -f "$B/web/dist/bundle.js" ]; then
  scripts/setup.sh
  scripts/setup-web.sh
  cmake -S . -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  ninja -C "$B" -j "${JOBS:-2}" groundsim-server groundsim groundsim-web
fi
url=${LCM_DEFAULT_URL:-udpm://239.255.76.67:7667?ttl=0}
if ! ip route show 224.0.0.0/4 2>/dev/null | grep -q . && ! ip route get 239.255.76.67 >/dev/null 2>&1; then
  echo "web.sh: no multicast route: sudo ip route add 224.0.0.0/4 dev lo" >&2
  exit 1
fi
bridge=""
"$B/server/lcm/groundsim-server" --lcm-url "$url" --quiet &
server=$!
trap 'kill $server $bridge 2>/dev/null; wait 2>/dev/null' EXIT INT TERM
"$B/web/bridge/groundsim-web" --lcm-url "$url" "$@" &
bridge=$!
wait $bridge
