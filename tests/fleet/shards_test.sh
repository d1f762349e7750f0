#!/usr/bin/env bash
# An experiment across hosts (issue 20): 3 servers in lab hosts 1-3 (a
# 3-member etcd in hosts 5-7); in host 4, Python's make_remote_vec(...,
# shards=3) spreads 12 environments over the 3 servers
# (tests/fleet/shards_check.py) and matches make_vec bit for bit. Then host 2
# is killed while another such env steps: the loop goes on without an
# exception, the lost shard's environments come back truncated on another
# server (the step's length is printed, a figure: docs/fleet.md). Exit 77
# where the lab cannot be made.
#   tests/fleet/shards_test.sh FLEET_LAB_SH GROUNDSIM_SERVER GROUNDSIM PYTHONPATH TASK PYTHON
set -euo pipefail
lab=$1 server=$2 client=$3 pypath=$4 task=$5 python=${6:-/usr/bin/python3}
. "$(dirname "$0")/fleet_lab_common.sh"
fleet_lab_begin fs
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
fleet_start_servers
fleet_wait_capacities  # every server registered its capacity
marker="$tmp/marker"
(for _ in $(seq 2400); do [ -e "$marker" ] && break; sleep 0.05; done
 [ -e "$marker" ] && sleep 1 && "$lab" kill "$name" 2) &
rc=0
"$lab" exec "$name" 4 env PYTHONPATH="$pypath" GROUNDSIM="$client" GROUNDSIM_KILL_MARKER="$marker" GROUNDSIM_SHARDS_BENCH="${GROUNDSIM_SHARDS_BENCH:-0}" \
  "$python" "$(dirname "$0")/shards_check.py" "$task" || rc=$?
if [ $rc != 0 ]; then
  for i in 1 2 3; do echo "--- server s$i (last lines)" >&2; tail -n 12 "$tmp/s$i.log" >&2; done
fi
exit $rc
