#!/usr/bin/env bash
# A 3-member etcd in three lab hosts (scripts/fleet_lab.sh) and a client in a
# fourth (cluster_check): the client keeps working while a member is cut off
# and when the leader's host is killed, and the killed member rejoins. The lab's name is unique to this run
# (the pid) and it is always torn down (trap). Exit 77 where the lab cannot
# be made (not root, no namespaces) or there is no etcd.
#   tests/fleet/cluster_test.sh FLEET_LAB_SH CLUSTER_CHECK
set -euo pipefail
lab=$1
check=$2
"$lab" check || exit $?
if ! command -v etcd >/dev/null || ! command -v etcdctl >/dev/null; then
  echo "SKIP: no etcd or etcdctl (apt-get install etcd-server etcd-client)" >&2
  exit 77
fi
name="fc$$"
tmp=$(mktemp -d /tmp/groundsim-cluster-XXXXXX)
cleanup() {
  "$lab" down "$name" || true
  rm -rf "$tmp"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
# labs of earlier runs killed before their trap ran (fc<pid> with that pid gone)
for old in $(ip netns list | awk '{print $1}' | sed -n 's/^gs-fc\([0-9]\{1,\}\)-sw$/\1/p'); do
  kill -0 "$old" 2>/dev/null || "$lab" down "fc$old" || true
done
"$lab" down "$name" 2>/dev/null || true
"$lab" up "$name" 4

"$lab" etcd-up "$name" "$tmp" 1 2 3 >/dev/null
rc=0
"$lab" exec "$name" 4 "$check" --lab "$lab" --name "$name" --dir "$tmp" \
  --endpoints http://192.0.2.1:2379,http://192.0.2.2:2379,http://192.0.2.3:2379 || rc=$?
if [ $rc != 0 ]; then
  for i in 1 2 3; do echo "--- etcd e$i (last lines)"; tail -n 15 "$tmp/e$i.log"; done
fi
exit $rc
